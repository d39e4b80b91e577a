#include "mapping/insertion_gate.hpp"

#include <cmath>

namespace vigs::mapping {

std::size_t gate_points(const KeyframeGaussians& kf, const RenderCamera& cam,
                        const RenderResult<float>& render, const GateSettings& s,
                        std::vector<char>& keep) {
  const std::size_t n = kf.points_c.size();
  keep.assign(n, 1);
  std::size_t kept = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f& p = kf.points_c[i];
    if (!(p.z() > 0.0f)) {
      ++kept;
      continue;
    }
    const long u = std::lround(cam.fx_px * p.x() / p.z() + cam.cx_px);
    const long v = std::lround(cam.fy_px * p.y() / p.z() + cam.cy_px);
    if (u < 0 || v < 0 || u >= render.width || v >= render.height) {
      ++kept;
      continue;
    }
    const int px = static_cast<int>(v) * render.width + static_cast<int>(u);
    const float alpha = render.alpha(px);
    bool missing = alpha < s.max_alpha;
    if (!missing) {
      const float z = render.depth[static_cast<std::size_t>(px)] / alpha;
      missing = std::abs(z - p.z()) > s.depth_rel * p.z();
    }
    if (!missing) {
      const float* c = &render.color[3 * static_cast<std::size_t>(px)];
      const float err = (std::abs(c[0] - kf.colors[i].x()) + std::abs(c[1] - kf.colors[i].y()) +
                         std::abs(c[2] - kf.colors[i].z())) /
                        3.0f;
      missing = err > s.color;
    }
    keep[i] = missing ? 1 : 0;
    kept += missing ? 1 : 0;
  }
  return kept;
}

}  // namespace vigs::mapping
