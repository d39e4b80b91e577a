#pragma once
// The camera a map is rendered from: pinhole intrinsics plus the world-to-camera pose.
#include <Eigen/Geometry>

#include "core/types/pinhole_camera.hpp"

namespace vigs::mapping {

/// Pixel centres sit at integer coordinates (OpenCV convention, as PinholeCamera::project);
/// gsplat's convention (centres at j + 0.5) is the same camera with cx, cy larger by 0.5.
struct RenderCamera {
  int width_px = 0;
  int height_px = 0;
  double fx_px = 0, fy_px = 0, cx_px = 0, cy_px = 0;
  double R_c_w[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  ///< row-major rotation world -> camera
  double t_c_w[3] = {0, 0, 0};                    ///< translation world -> camera, metres

  static RenderCamera from(const PinholeCamera& k, const Eigen::Isometry3d& T_w_c) {
    RenderCamera c;
    c.width_px = k.width_px;
    c.height_px = k.height_px;
    c.fx_px = k.fx_px;
    c.fy_px = k.fy_px;
    c.cx_px = k.cx_px;
    c.cy_px = k.cy_px;
    const Eigen::Isometry3d T_c_w = T_w_c.inverse();
    for (int r = 0; r < 3; ++r) {
      for (int k2 = 0; k2 < 3; ++k2) c.R_c_w[3 * r + k2] = T_c_w.linear()(r, k2);
      c.t_c_w[r] = T_c_w.translation()(r);
    }
    return c;
  }
};

}  // namespace vigs::mapping
