#include <gtest/gtest.h>

#include <cmath>

#include "core/geometry/se3.hpp"
#include "core/geometry/so3.hpp"
#include "sim/floor_plan.hpp"
#include "sim/imu_synth.hpp"
#include "sim/spline_trajectory.hpp"
#include "tests/sim/imu_integration.hpp"

namespace vigs::sim {
namespace {

/// Integrates noise-free IMU samples of the smooth office route (seed 2).
test::IntegrationError integrate(double rate_hz, double t0, double seconds) {
  const Scene s = make_preset("office", 2);
  const SplineTrajectory traj(s.route);
  return test::integrate_imu(traj, rate_hz, t0, seconds);
}

TEST(ImuSynthesis, NoiseFreeImuIntegratesBackToGroundTruth) {
  // On straights and through the first corner of the office route (t = 24..29 s).
  for (double t0 : {3.0, 20.0, 24.0, 60.0}) {
    const test::IntegrationError e = integrate(1000.0, t0, 5.0);
    // Measured (office seed 2): at most 8e-7 m, 7e-8 rad, 3e-7 m/s; bounds leave 10x.
    EXPECT_LT(e.position_m, 1e-5) << t0;
    EXPECT_LT(e.rotation_rad, 1e-6) << t0;
    EXPECT_LT(e.velocity_mps, 5e-6) << t0;
    // At the recorded 200 Hz (measured: 2e-5 m, 1.7e-6 rad) the discretisation error of the
    // trapezoidal rule is still far below a millimetre.
    const test::IntegrationError e200 = integrate(200.0, t0, 5.0);
    EXPECT_LT(e200.position_m, 2e-4) << t0;
    EXPECT_LT(e200.rotation_rad, 2e-5) << t0;
  }
}

TEST(ImuSynthesis, StandstillMeasuresGravityUpAndZeroRate) {
  const Scene s = make_preset("office", 2);
  const SplineTrajectory traj(s.route);
  config::ImuSettings cfg;
  ImuSynthesizer imu(cfg, 1, false);
  const BodyState st = traj.state(0.5);
  const ImuSample m = imu.measure(st, 0);
  // Specific force at rest is +g along world up, seen in the (slightly swaying) body frame.
  const Eigen::Vector3d f_w = st.R_w_b * Eigen::Vector3d(m.accel_mps2);
  EXPECT_NEAR(f_w.z(), cfg.gravity_mps2, 1e-2);  // sway adds a tiny centripetal part
  EXPECT_NEAR(Eigen::Vector3d(m.accel_mps2).norm(), cfg.gravity_mps2, 1e-2);
}

TEST(ImuSynthesis, NoiseAndBiasWalkFollowTheConfiguredDensities) {
  const Scene s = make_preset("office", 2);
  const SplineTrajectory traj(s.route);
  config::ImuSettings cfg;
  ImuSynthesizer noisy(cfg, 9, true), clean(cfg, 9, false);
  const int n = 20000;  // 100 s at 200 Hz
  double sg = 0, sa = 0;
  for (int k = 0; k < n; ++k) {
    const BodyState st = traj.state(10.0 + k * 0.005);
    const Eigen::Vector3d bg = noisy.gyro_bias(), ba = noisy.accel_bias();  // used by sample k
    const ImuSample a = noisy.measure(st, k);
    const ImuSample b = clean.measure(st, k);
    const double dg = a.gyro_rps[0] - b.gyro_rps[0] - bg.x();
    const double da = a.accel_mps2[1] - b.accel_mps2[1] - ba.y();
    sg += dg * dg;
    sa += da * da;
  }
  const double expected_g = cfg.gyro_noise_density * std::sqrt(cfg.rate_hz);
  const double expected_a = cfg.accel_noise_density * std::sqrt(cfg.rate_hz);
  // 20000 samples: the sample deviation is within ~1% of the true one; allow 5%.
  EXPECT_NEAR(std::sqrt(sg / n), expected_g, 0.05 * expected_g);
  EXPECT_NEAR(std::sqrt(sa / n), expected_a, 0.05 * expected_a);
  // Bias random walk: after 100 s the accel bias has moved by about 3e-3 * sqrt(100) = 0.03.
  EXPECT_GT(noisy.accel_bias().norm(), 1e-3);
  EXPECT_LT(noisy.accel_bias().norm(), 0.2);
  // Same seed, same noise: deterministic.
  ImuSynthesizer again(cfg, 9, true);
  const ImuSample x = again.measure(traj.state(10.0), 0);
  ImuSynthesizer first(cfg, 9, true);
  const ImuSample y = first.measure(traj.state(10.0), 0);
  EXPECT_EQ(x.gyro_rps[2], y.gyro_rps[2]);
}

}  // namespace
}  // namespace vigs::sim
