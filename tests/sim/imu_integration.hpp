#pragma once
// Integrates noise-free synthesised IMU samples back into a trajectory (trapezoidal in
// rotation, velocity and position) from the true state at t0, for the IMU tests.
#include <cmath>

#include "core/geometry/se3.hpp"
#include "core/geometry/so3.hpp"
#include "sim/imu_synth.hpp"
#include "sim/trajectory.hpp"

namespace vigs::sim::test {

struct IntegrationError {
  double position_m = 0, rotation_rad = 0, velocity_mps = 0;
};

/// Integrates for `seconds` at `rate_hz` and compares with the trajectory at the end.
inline IntegrationError integrate_imu(const Trajectory& traj, double rate_hz, double t0,
                                      double seconds) {
  config::ImuSettings cfg;
  cfg.rate_hz = rate_hz;
  ImuSynthesizer imu(cfg, 1, /*noisy=*/false);
  const double dt = 1.0 / rate_hz;
  const Eigen::Vector3d g(0, 0, -cfg.gravity_mps2);
  BodyState st = traj.state(t0);
  Eigen::Matrix3d R = st.R_w_b;
  Eigen::Vector3d v = st.v_w_mps, p = st.p_w_m;
  ImuSample m0 = imu.measure(st, 0);
  const int n = static_cast<int>(std::lround(seconds * rate_hz));
  for (int k = 1; k <= n; ++k) {
    const ImuSample m1 = imu.measure(traj.state(t0 + k * dt), k);
    const Eigen::Vector3d w0(m0.gyro_rps), w1(m1.gyro_rps);
    const Eigen::Vector3d f0(m0.accel_mps2), f1(m1.accel_mps2);
    const Eigen::Matrix3d R1 = R * geometry::so3_exp<double>(0.5 * (w0 + w1) * dt);
    const Eigen::Vector3d a0 = R * f0 + g, a1 = R1 * f1 + g;
    const Eigen::Vector3d v1 = v + 0.5 * (a0 + a1) * dt;
    p += 0.5 * (v + v1) * dt;
    v = v1;
    R = R1;
    m0 = m1;
  }
  const BodyState end = traj.state(t0 + n * dt);
  return {(p - end.p_w_m).norm(), geometry::rotation_angle(R.transpose() * end.R_w_b),
          (v - end.v_w_mps).norm()};
}

}  // namespace vigs::sim::test
