#pragma once
// A smooth analytic body trajectory with exact IMU readings, for tests and benchmarks of
// preintegration and the initial guess: position and Z-Y-X Euler angles are sums of sines,
// so velocity, acceleration and body rates are known in closed form.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>

#include "core/types/imu_sample.hpp"

namespace vigs::inertial {

struct MotionPoint {
  Eigen::Matrix3d R_w_b;
  Eigen::Vector3d p_w_b_m;
  Eigen::Vector3d v_w_b_mps;
  Eigen::Vector3d a_w_mps2;     ///< kinematic acceleration in world
  Eigen::Vector3d omega_b_rps;  ///< body angular rate
};

/// Hand-held-like motion: ~1 m / ~30 deg amplitudes, periods of a few seconds.
struct SyntheticMotion {
  Eigen::Vector3d amp_m{1.0, 0.8, 0.3};
  Eigen::Vector3d freq_rps{0.9, 1.3, 1.7};     ///< angular frequencies of x, y, z, rad/s
  Eigen::Vector3d ang_amp_rad{0.2, 0.3, 0.6};  ///< roll, pitch, yaw amplitudes
  Eigen::Vector3d ang_freq_rps{1.1, 0.7, 0.5};
  Eigen::Vector3d p0_m{0.5, -0.3, 1.2};

  [[nodiscard]] MotionPoint at(double t) const {
    MotionPoint m;
    Eigen::Vector3d e, de;  // roll, pitch, yaw and their rates
    for (int k = 0; k < 3; ++k) {
      const double w = freq_rps[k];
      m.p_w_b_m[k] = p0_m[k] + amp_m[k] * std::sin(w * t);
      m.v_w_b_mps[k] = amp_m[k] * w * std::cos(w * t);
      m.a_w_mps2[k] = -amp_m[k] * w * w * std::sin(w * t);
      const double wa = ang_freq_rps[k];
      e[k] = ang_amp_rad[k] * std::sin(wa * t + 0.3 * k);
      de[k] = ang_amp_rad[k] * wa * std::cos(wa * t + 0.3 * k);
    }
    const double r = e[0], pch = e[1], y = e[2];
    m.R_w_b = (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) *
               Eigen::AngleAxisd(pch, Eigen::Vector3d::UnitY()) *
               Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
                  .toRotationMatrix();
    // Body rates of Z-Y-X Euler angles.
    m.omega_b_rps = {de[0] - de[2] * std::sin(pch),
                     de[1] * std::cos(r) + de[2] * std::cos(pch) * std::sin(r),
                     de[2] * std::cos(pch) * std::cos(r) - de[1] * std::sin(r)};
    return m;
  }

  /// Exact reading at t_ns (motion time t = t_ns * 1e-9) for gravity g_w.
  [[nodiscard]] ImuSample sample(std::int64_t t_ns, const Eigen::Vector3d& g_w_mps2) const {
    const MotionPoint m = at(1e-9 * static_cast<double>(t_ns));
    const Eigen::Vector3d f_b = m.R_w_b.transpose() * (m.a_w_mps2 - g_w_mps2);
    ImuSample s;
    s.t_ns = t_ns;
    for (int k = 0; k < 3; ++k) {
      s.gyro_rps[k] = m.omega_b_rps[k];
      s.accel_mps2[k] = f_b[k];
    }
    return s;
  }
};

}  // namespace vigs::inertial
