#pragma once
// The camera's pose in the IMU body frame, T_b_c, as the robot file's extrinsics give it: the
// one conversion the simulator, the inertial front end, replay and evaluation share.
#include <cstddef>

#include "core/config/extrinsics_settings.hpp"
#include "core/geometry/se3.hpp"

namespace vigs::geometry {

/// T_b_c from extrinsics.R_b_c (row-major) and extrinsics.t_b_c_m.
inline Pose body_from_camera(const config::ExtrinsicsSettings& e) {
  Pose T_b_c = Pose::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T_b_c.linear()(r, c) = e.R_b_c[static_cast<std::size_t>(r * 3 + c)];
  }
  T_b_c.translation() = Eigen::Vector3d(e.t_b_c_m[0], e.t_b_c_m[1], e.t_b_c_m[2]);
  return T_b_c;
}

}  // namespace vigs::geometry
