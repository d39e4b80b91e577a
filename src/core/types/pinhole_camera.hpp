#pragma once
#include <Eigen/Core>

#include "core/config/camera_settings.hpp"

namespace vigs {

/// Pinhole intrinsics of a depth-registered colour image (no distortion).
struct PinholeCamera {
  int width_px = 0;
  int height_px = 0;
  double fx_px = 0, fy_px = 0, cx_px = 0, cy_px = 0;

  static PinholeCamera from_settings(const config::CameraSettings& s) {
    return {s.width_px, s.height_px, s.fx_px, s.fy_px, s.cx_px, s.cy_px};
  }
  /// Pixel (u, v) at depth z (metres) to a point in the camera frame (x right, y down, z fwd).
  [[nodiscard]] Eigen::Vector3d back_project(double u, double v, double z_m) const {
    return {(u - cx_px) * z_m / fx_px, (v - cy_px) * z_m / fy_px, z_m};
  }
  /// Camera-frame point to pixel; z must be positive.
  [[nodiscard]] Eigen::Vector2d project(const Eigen::Vector3d& p_c) const {
    return {fx_px * p_c.x() / p_c.z() + cx_px, fy_px * p_c.y() / p_c.z() + cy_px};
  }
};

}  // namespace vigs
