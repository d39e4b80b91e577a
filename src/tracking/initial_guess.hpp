#pragma once
// Where GICP starts for a new frame (T_w_c guess):
//  - imu: the IMU-propagated pose handed in by the caller (the paper; the inertial module's
//    preintegration composes it). Without one, the tracker falls back to constant velocity
//    and says so in its output;
//  - constant_velocity: the last inter-frame motion repeated, scaled to the new interval;
//  - previous_pose: the last pose (GS-ICP SLAM's baseline).
#include <cstdint>
#include <string_view>

#include "core/config/tracking_components.hpp"
#include "core/geometry/se3.hpp"

namespace vigs::tracking {

using config::InitialGuessMode;  // declared with the settings (config/tracking_components.hpp)

inline InitialGuessMode initial_guess_from_string(std::string_view name) {
  if (name == "constant_velocity") return InitialGuessMode::constant_velocity;
  if (name == "previous_pose") return InitialGuessMode::previous_pose;
  return InitialGuessMode::imu;
}

/// Constant-velocity prediction: the body-frame motion T_prev^-1 * T_last over
/// (t_last - t_prev) is repeated over (t_new - t_last), scaling its rotation vector and
/// translation by the ratio of the intervals (first order in the scale). Non-increasing or
/// missing stamps fall back to one whole increment.
inline geometry::Pose predict_constant_velocity(const geometry::Pose& T_w_prev,
                                                std::int64_t t_prev_ns,
                                                const geometry::Pose& T_w_last,
                                                std::int64_t t_last_ns, std::int64_t t_new_ns) {
  const geometry::Pose delta = T_w_prev.inverse() * T_w_last;
  double scale = 1.0;
  if (t_last_ns > t_prev_ns && t_new_ns > t_last_ns) {
    scale = static_cast<double>(t_new_ns - t_last_ns) / static_cast<double>(t_last_ns - t_prev_ns);
  }
  const Eigen::Vector3d phi = geometry::so3_log<double>(delta.linear()) * scale;
  return T_w_last * geometry::make_pose(phi, Eigen::Vector3d(delta.translation() * scale));
}

}  // namespace vigs::tracking
