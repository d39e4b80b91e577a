#include "pipeline/moving_pixels.hpp"

#include <algorithm>
#include <cmath>

namespace vigs::pipeline {

std::size_t mask_moving_pixels(const tracking::Keyframe& kf, const PinholeCamera& camera,
                               int stride_px, int dilation_px, ImageF32& depth_m) {
  const tracking::GaussianCloud& c = kf.cloud_c;
  const int w = depth_m.width, h = depth_m.height;
  if (kf.moving.size() != c.size() || w != camera.width_px || h != camera.height_px ||
      depth_m.channels != 1)
    return 0;
  const int half = std::max(0, stride_px) / 2 + std::max(0, dilation_px);
  std::size_t marked = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (kf.moving[i] == 0) continue;
    const Eigen::Vector3f& p = c.points_m[i];
    if (!(p.z() > 0.0f)) continue;
    const long u = std::lround(camera.fx_px * p.x() / p.z() + camera.cx_px);
    const long v = std::lround(camera.fy_px * p.y() / p.z() + camera.cy_px);
    const int u0 = static_cast<int>(std::clamp<long>(u - half, 0, w));
    const int u1 = static_cast<int>(std::clamp<long>(u + half + 1, 0, w));
    const int v0 = static_cast<int>(std::clamp<long>(v - half, 0, h));
    const int v1 = static_cast<int>(std::clamp<long>(v + half + 1, 0, h));
    for (int vv = v0; vv < v1; ++vv) {
      float* row = depth_m.data.data() + static_cast<std::size_t>(vv) * w;
      for (int uu = u0; uu < u1; ++uu) {
        if (row[uu] >= 0.0f) ++marked;
        row[uu] = -1.0f;
      }
    }
  }
  return marked;
}

}  // namespace vigs::pipeline
