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
  /// Edge of this camera's pixel in pixels of the sensor's camera it stands for: 1 at the
  /// sensor's resolution, 2 one pyramid level down (half_res_camera). The rasterizer's
  /// low-pass filter is set in sensor pixels (RasterSettings::eps2d_px2) and is divided by the
  /// square of this, so that it blurs a Gaussian by the same amount in the scene at every
  /// resolution: a Gaussian trained at half resolution then covers at full resolution what it
  /// covered in training (BENCHMARKS.md, thirty-eighth session).
  double pixel_size = 1.0;

  /// The low-pass filter's variance in this camera's pixels^2, for one of `sensor_px2`.
  [[nodiscard]] double lowpass_px2(double sensor_px2) const {
    return sensor_px2 / (pixel_size * pixel_size);
  }

  static RenderCamera from(const PinholeCamera& k, const Eigen::Isometry3d& T_w_c) {
    RenderCamera c;
    c.width_px = k.width_px;
    c.height_px = k.height_px;
    c.fx_px = k.fx_px;
    c.fy_px = k.fy_px;
    c.cx_px = k.cx_px;
    c.cy_px = k.cy_px;
    c.set_T_w_c(T_w_c);
    return c;
  }

  /// The camera's pose in the world.
  [[nodiscard]] Eigen::Isometry3d T_w_c() const {
    Eigen::Isometry3d T_c_w = Eigen::Isometry3d::Identity();
    T_c_w.linear() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R_c_w);
    T_c_w.translation() = Eigen::Vector3d(t_c_w[0], t_c_w[1], t_c_w[2]);
    return T_c_w.inverse();
  }
  void set_T_w_c(const Eigen::Isometry3d& T_w_c) {
    const Eigen::Isometry3d T_c_w = T_w_c.inverse();
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) R_c_w[3 * r + k] = T_c_w.linear()(r, k);
      t_c_w[r] = T_c_w.translation()(r);
    }
  }
};

}  // namespace vigs::mapping
