#include "mapping/rgbd_keyframe.hpp"

#include <cmath>
#include <stdexcept>

namespace vigs::mapping {

KeyframeGaussians keyframe_from_rgbd(const PinholeCamera& cam, const io::ImageU8& rgb,
                                     const io::ImageF32& depth_m, const Eigen::Isometry3d& T_w_c,
                                     const RgbdSampling& s) {
  if (rgb.width != depth_m.width || rgb.height != depth_m.height || rgb.channels != 3 ||
      depth_m.channels != 1)
    throw std::invalid_argument("keyframe_from_rgbd: colour must be RGB and match the depth size");
  KeyframeGaussians kf;
  kf.T_w_c = T_w_c;
  const int st = std::max(1, s.stride_px);
  auto valid = [&](float z) { return z >= s.min_depth_m && z <= s.max_depth_m; };
  for (int v = 0; v < depth_m.height; v += st) {
    for (int u = 0; u < depth_m.width; u += st) {
      const float z0 = depth_m.at(u, v);
      if (!valid(z0)) continue;
      Eigen::Vector3d pts[9];
      int n = 0;
      for (int dv = -1; dv <= 1; ++dv) {
        for (int du = -1; du <= 1; ++du) {
          const int uu = u + du * st, vv = v + dv * st;
          if (uu < 0 || vv < 0 || uu >= depth_m.width || vv >= depth_m.height) continue;
          const float z = depth_m.at(uu, vv);
          if (!valid(z) || std::abs(z - z0) > s.max_relative_jump * z0) continue;
          pts[n++] = cam.back_project(uu, vv, z);
        }
      }
      if (n < 4) continue;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (int k = 0; k < n; ++k) mean += pts[k];
      mean /= n;
      Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
      for (int k = 0; k < n; ++k) cov += (pts[k] - mean) * (pts[k] - mean).transpose();
      cov /= n;
      kf.points_c.push_back(cam.back_project(u, v, z0).cast<float>());
      kf.covariances_c.push_back(cov.cast<float>());
      kf.colors.emplace_back(rgb.at(u, v, 0) / 255.0f, rgb.at(u, v, 1) / 255.0f,
                             rgb.at(u, v, 2) / 255.0f);
    }
  }
  return kf;
}

}  // namespace vigs::mapping
