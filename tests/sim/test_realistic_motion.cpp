#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "sim/floor_plan.hpp"
#include "sim/realistic_motion.hpp"
#include "sim/simulator.hpp"
#include "tests/sim/derivative_check.hpp"
#include "tests/sim/imu_integration.hpp"

namespace vigs::sim {
namespace {

RealisticMotion office_motion(std::uint64_t seed) {
  const Scene s = make_preset("office", seed);
  return RealisticMotion(SplineTrajectory(s.route), seed);
}

/// Heading of the body x axis in the floor plane.
double heading(const BodyState& st) {
  return std::atan2(st.R_w_b(1, 0), st.R_w_b(0, 0));
}

/// Horizontal speed over a 0.2 s window (averages the vibration out).
double smoothed_speed(const Trajectory& tr, double t) {
  return (tr.state(t + 0.1).p_w_m - tr.state(t - 0.1).p_w_m).head<2>().norm() / 0.2;
}

TEST(RealisticMotion, AnalyticDerivativesMatchFiniteDifferences) {
  const RealisticMotion traj = office_motion(3);
  // The 8-30 Hz vibration's third derivative limits the acceleration check's precision.
  test::expect_analytic_derivatives(traj, 0.013, 180.0, 0.377, 1e-5, {1e-6, 2e-4, 1e-6});
}

TEST(RealisticMotion, NoiseFreeImuIntegratesBackToGroundTruth) {
  const RealisticMotion traj = office_motion(3);
  // 5 s windows from the start standstill over the first stops and corners. The 8-30 Hz
  // vibration makes the trapezoidal rule's error visible; it falls with dt^2 (measured, seed
  // 3: 1 kHz at most 0.29 mm, 3e-6 rad, 0.11 mm/s; 4 kHz at most 0.046 mm, 1.9e-7 rad,
  // 0.015 mm/s), so what is left is discretisation, not a wrong derivative.
  double sum_1k = 0, sum_4k = 0;
  for (double t0 = 0.0; t0 < 60.0; t0 += 5.0) {
    const test::IntegrationError e = test::integrate_imu(traj, 4000.0, t0, 5.0);
    EXPECT_LT(e.position_m, 1e-4) << t0;
    EXPECT_LT(e.rotation_rad, 1e-6) << t0;
    EXPECT_LT(e.velocity_mps, 5e-5) << t0;
    sum_4k += e.position_m;
    sum_1k += test::integrate_imu(traj, 1000.0, t0, 5.0).position_m;
  }
  EXPECT_LT(sum_4k, sum_1k / 4.0);
}

TEST(RealisticMotion, StopsBrakesAndQuickTurns) {
  for (std::uint64_t seed : {3u, 5u}) {
    const RealisticMotion traj = office_motion(seed);
    const double dt = 0.01;
    double longest_stop_s = 0, stop_s = 0, max_accel = 0, max_yaw_rate = 0;
    double prev_speed = smoothed_speed(traj, 4.0);
    int hard_ramps = 0;  // 0.1 s steps with |d speed / dt| >= 1 m/s^2
    // After the start standstill, within the first minute.
    for (double t = 4.0 + dt; t < 60.0; t += dt) {
      const BodyState st = traj.state(t);
      stop_s = st.v_w_mps.norm() == 0.0 ? stop_s + dt : 0.0;
      longest_stop_s = std::max(longest_stop_s, stop_s);
      const double speed = smoothed_speed(traj, t);
      const double accel = std::abs(speed - prev_speed) / dt;
      prev_speed = speed;
      max_accel = std::max(max_accel, accel);
      hard_ramps += accel >= 1.0;
      double dyaw = heading(traj.state(t + 0.05)) - heading(traj.state(t - 0.05));
      dyaw = std::remainder(dyaw, 2 * M_PI);
      max_yaw_rate = std::max(max_yaw_rate, std::abs(dyaw) / 0.1);
    }
    EXPECT_GE(longest_stop_s, 1.0) << seed;  // a real standstill mid-route
    EXPECT_GT(max_accel, 1.0) << seed;       // braking / accelerating at 1-2 m/s^2
    EXPECT_LT(max_accel, 2.6) << seed;
    EXPECT_GT(hard_ramps, 20) << seed;                   // more than a moment
    EXPECT_GT(max_yaw_rate, 80.0 * M_PI / 180) << seed;  // quick turns at corners
    EXPECT_LT(max_yaw_rate, 140.0 * M_PI / 180) << seed;
  }
}

TEST(RealisticMotion, WalkingBobAndVibration) {
  const RealisticMotion traj = office_motion(3);
  // While walking: vertical bob of centimetres, and vibration that shows as accelerations
  // and body rates far above the route's own (sampled at 1 kHz for 10 s).
  double z_min = 1e9, z_max = -1e9, max_vertical_accel = 0;
  for (double t = 30.0; t < 40.0; t += 0.001) {
    const BodyState st = traj.state(t);
    z_min = std::min(z_min, st.p_w_m.z());
    z_max = std::max(z_max, st.p_w_m.z());
    max_vertical_accel = std::max(max_vertical_accel, std::abs(st.a_w_mps2.z()));
  }
  EXPECT_GT(z_max - z_min, 0.01);
  EXPECT_LT(z_max - z_min, 0.06);
  EXPECT_GT(max_vertical_accel, 2.0);
  // The smooth route has none of it: it stays at its height.
  const Scene s = make_preset("office", 3);
  const SplineTrajectory smooth(s.route);
  EXPECT_NEAR(smooth.state(35.0).p_w_m.z(), smooth.state(30.0).p_w_m.z(), 1e-12);
}

TEST(RealisticMotion, SameSeedSameMotionOtherSeedOther) {
  const RealisticMotion a = office_motion(4), b = office_motion(4);
  const Scene s = make_preset("office", 4);
  const RealisticMotion c(SplineTrajectory(s.route), 5);  // same route, other seed
  EXPECT_EQ(a.duration_s(), b.duration_s());
  bool differs = false;
  for (double t = 0; t < 120.0; t += 0.37) {
    const BodyState x = a.state(t), y = b.state(t), z = c.state(t);
    EXPECT_EQ(x.p_w_m, y.p_w_m) << t;
    EXPECT_EQ(x.a_w_mps2, y.a_w_mps2) << t;
    EXPECT_EQ(x.omega_b_rps, y.omega_b_rps) << t;
    differs = differs || (x.p_w_m - z.p_w_m).norm() > 0.01;
  }
  EXPECT_TRUE(differs);
}

TEST(RealisticMotion, StaysOnCorridorCentreLines) {
  const FloorPlanParams p = office_params();
  const Scene s = generate_floor_plan(p, 5);
  const RealisticMotion traj(SplineTrajectory(s.route), 5);
  EXPECT_GT(traj.duration_s(), SplineTrajectory(s.route).duration_s());  // stops take time
  for (double t = 0; t <= traj.duration_s(); t += 0.1) {
    const Eigen::Vector3d q = traj.state(t).p_w_m;
    double off = 1e9;
    for (double c : p.corridor_centers_m)
      off = std::min({off, std::abs(q.x() - c), std::abs(q.y() - c)});
    EXPECT_LT(off, 0.35) << t;  // the smooth route's corner cut plus under a millimetre
  }
}

TEST(RealisticMotion, SimMotionKeySelectsTheProfile) {
  config::RobotConfig cfg;
  cfg.sim.humans = 0;
  cfg.sim.seed = 3;
  const RealisticMotion expected = office_motion(3);
  cfg.sim.motion = "realistic";
  const Simulator realistic(cfg);
  cfg.sim.motion = "smooth";
  const Simulator smooth(cfg);
  for (double t : {17.3, 33.3, 58.1}) {
    EXPECT_EQ(realistic.trajectory().state(t).p_w_m, expected.state(t).p_w_m) << t;
    EXPECT_GT((smooth.trajectory().state(t).p_w_m - expected.state(t).p_w_m).norm(), 0.01) << t;
  }
}

}  // namespace
}  // namespace vigs::sim
