#include "mapping/rgbd_keyframe.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace vigs::mapping {

namespace {

template <class DepthAt>
KeyframeGaussians from_rgbd(const PinholeCamera& cam, const RgbdView& frame, DepthAt depth_at,
                            const Eigen::Isometry3d& T_w_c, const RgbdSampling& s) {
  KeyframeGaussians kf;
  kf.T_w_c = T_w_c;
  const int st = std::max(1, s.stride_px);
  kf.sample_angle_rad = 2.0 * st / (cam.fx_px + cam.fy_px);
  const int width = frame.width_px, height = frame.height_px;
  auto valid = [&](float z) { return z >= s.min_depth_m && z <= s.max_depth_m; };
  for (int v = 0; v < height; v += st) {
    for (int u = 0; u < width; u += st) {
      const float z0 = depth_at(u, v);
      if (!valid(z0)) continue;
      Eigen::Vector3d pts[9];
      int n = 0;
      for (int dv = -1; dv <= 1; ++dv) {
        for (int du = -1; du <= 1; ++du) {
          const int uu = u + du * st, vv = v + dv * st;
          if (uu < 0 || vv < 0 || uu >= width || vv >= height) continue;
          const float z = depth_at(uu, vv);
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
      const std::array<std::uint8_t, 3> rgb = frame.rgb_at(u, v);
      kf.points_c.push_back(cam.back_project(u, v, z0).cast<float>());
      kf.covariances_c.push_back(cov.cast<float>());
      kf.colors.emplace_back(rgb[0] / 255.0f, rgb[1] / 255.0f, rgb[2] / 255.0f);
    }
  }
  return kf;
}

}  // namespace

void footprint_colours(const PinholeCamera& cam, const RgbdView& frame, int stride_px,
                       KeyframeGaussians& kf, double max_relative_jump) {
  if (!frame.has_colour()) return;
  const int h = std::max(0, stride_px / 2);
  const int width = frame.width_px, height = frame.height_px;
  frame.with_depth_m([&](auto depth_at) {
    for (std::size_t i = 0; i < kf.points_c.size(); ++i) {
      const Eigen::Vector3f& p = kf.points_c[i];
      if (!(p.z() > 0.0f)) continue;
      const long u0 = std::lround(cam.fx_px * p.x() / p.z() + cam.cx_px);
      const long v0 = std::lround(cam.fy_px * p.y() / p.z() + cam.cy_px);
      if (u0 < 0 || v0 < 0 || u0 >= width || v0 >= height) continue;
      const float jump = static_cast<float>(max_relative_jump) * p.z();
      float sum[3] = {0, 0, 0};
      int n = 0;
      for (int v = std::max(0, static_cast<int>(v0) - h);
           v <= std::min(height - 1, static_cast<int>(v0) + h); ++v) {
        for (int u = std::max(0, static_cast<int>(u0) - h);
             u <= std::min(width - 1, static_cast<int>(u0) + h); ++u) {
          const float z = depth_at(u, v);
          if (!(std::abs(z - p.z()) <= jump)) continue;
          const std::array<std::uint8_t, 3> c = frame.rgb_at(u, v);
          for (int k = 0; k < 3; ++k) sum[k] += c[static_cast<std::size_t>(k)];
          ++n;
        }
      }
      if (n > 0)
        kf.colors[i] = Eigen::Vector3f(sum[0], sum[1], sum[2]) / (255.0f * static_cast<float>(n));
    }
  });
}

KeyframeGaussians keyframe_from_rgbd(const PinholeCamera& cam, const RgbdView& frame,
                                     const Eigen::Isometry3d& T_w_c, const RgbdSampling& s) {
  KeyframeGaussians kf =
      frame.with_depth_m([&](auto depth_at) { return from_rgbd(cam, frame, depth_at, T_w_c, s); });
  footprint_colours(cam, frame, s.stride_px, kf, s.max_relative_jump);
  return kf;
}

KeyframeGaussians keyframe_from_rgbd(const PinholeCamera& cam, const ImageU8& rgb,
                                     const ImageF32& depth_m, const Eigen::Isometry3d& T_w_c,
                                     const RgbdSampling& s) {
  if (rgb.width != depth_m.width || rgb.height != depth_m.height || rgb.channels != 3 ||
      depth_m.channels != 1)
    throw std::invalid_argument("keyframe_from_rgbd: colour must be RGB and match the depth size");
  return keyframe_from_rgbd(cam, rgbd_view(0, depth_m, rgb), T_w_c, s);
}

}  // namespace vigs::mapping
