#include "mapping/half_res_view.hpp"

#include <algorithm>
#include <cstddef>

namespace vigs::mapping {

RenderCamera half_res_camera(const RenderCamera& full) {
  RenderCamera c = full;
  c.width_px = full.width_px / 2;
  c.height_px = full.height_px / 2;
  c.fx_px = full.fx_px / 2.0;
  c.fy_px = full.fy_px / 2.0;
  c.cx_px = (full.cx_px - 0.5) / 2.0;
  c.cy_px = (full.cy_px - 0.5) / 2.0;
  c.pixel_size = 2.0 * full.pixel_size;
  return c;
}

namespace {

float block_depth(const float d[4]) {
  float nearest = 0.0f;
  for (int k = 0; k < 4; ++k) {
    if (d[k] < 0.0f) return -1.0f;  // a moving pixel masks the block
    if (d[k] > 0.0f && (nearest == 0.0f || d[k] < nearest)) nearest = d[k];
  }
  if (nearest == 0.0f) return 0.0f;
  const float limit = nearest * (1.0f + kHalfResDepthTolerance);
  float sum = 0.0f;
  int n = 0;
  for (int k = 0; k < 4; ++k) {
    if (d[k] > 0.0f && d[k] <= limit) {
      sum += d[k];
      ++n;
    }
  }
  return sum / static_cast<float>(n);
}

}  // namespace

void make_half_res_view(const RenderCamera& camera, const float* rgb, const float* depth_m,
                        HalfResView& out) {
  out.camera = half_res_camera(camera);
  const int w = out.camera.width_px, h = out.camera.height_px, fw = camera.width_px;
  const std::size_t np = static_cast<std::size_t>(std::max(0, w)) * std::max(0, h);
  out.rgb.resize(3 * np);
  if (depth_m)
    out.depth_m.resize(np);
  else
    out.depth_m.clear();
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t q = static_cast<std::size_t>(y) * w + x;
      const std::size_t p[4] = {static_cast<std::size_t>(2 * y) * fw + 2 * x,
                                static_cast<std::size_t>(2 * y) * fw + 2 * x + 1,
                                static_cast<std::size_t>(2 * y + 1) * fw + 2 * x,
                                static_cast<std::size_t>(2 * y + 1) * fw + 2 * x + 1};
      for (int c = 0; c < 3; ++c)
        out.rgb[3 * q + c] =
            0.25f * (rgb[3 * p[0] + c] + rgb[3 * p[1] + c] + rgb[3 * p[2] + c] + rgb[3 * p[3] + c]);
      if (depth_m) {
        const float d[4] = {depth_m[p[0]], depth_m[p[1]], depth_m[p[2]], depth_m[p[3]]};
        out.depth_m[q] = block_depth(d);
      }
    }
  }
}

}  // namespace vigs::mapping
