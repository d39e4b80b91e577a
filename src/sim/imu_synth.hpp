#pragma once
// IMU samples from the trajectory's analytic derivatives: gyro = omega_b + b_g + n_g,
// accel = R_w_b^T (a_w - g_w) + b_a + n_a with g_w = (0, 0, -g). White noise has standard
// deviation density / sqrt(dt); biases follow random walks with step random_walk * sqrt(dt)
// (continuous-time densities as in Kalibr / config::ImuSettings). Biases start at zero.
#include <Eigen/Core>
#include <cstdint>

#include "core/config/imu_settings.hpp"
#include "core/types/imu_sample.hpp"
#include "sim/rng.hpp"
#include "sim/spline_trajectory.hpp"

namespace vigs::sim {

class ImuSynthesizer {
 public:
  /// `noisy` = false gives the exact kinematic measurements (tests).
  ImuSynthesizer(const config::ImuSettings& settings, std::uint64_t seed, bool noisy = true);

  /// The measurement at `state`; advances the bias random walks by one sample period.
  ImuSample measure(const BodyState& state, std::int64_t t_ns);

  [[nodiscard]] const Eigen::Vector3d& gyro_bias() const { return b_g_; }
  [[nodiscard]] const Eigen::Vector3d& accel_bias() const { return b_a_; }

 private:
  config::ImuSettings s_;
  Rng rng_;
  bool noisy_;
  double dt_s_;
  Eigen::Vector3d b_g_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d b_a_ = Eigen::Vector3d::Zero();
};

}  // namespace vigs::sim
