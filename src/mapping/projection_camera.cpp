#include "mapping/projection_avx2.hpp"

namespace vigs::mapping {

// The same conversions as project_gaussian() and projection_state() (projection.hpp).
ProjectionCamera ProjectionCamera::from(const RenderCamera& cam, float eps2d_px2) {
  ProjectionCamera c{};
  for (int k = 0; k < 9; ++k) c.R_c_w[k] = static_cast<float>(cam.R_c_w[k]);
  for (int k = 0; k < 3; ++k) c.t_c_w[k] = static_cast<float>(cam.t_c_w[k]);
  c.fx = static_cast<float>(cam.fx_px);
  c.fy = static_cast<float>(cam.fy_px);
  c.cx = static_cast<float>(cam.cx_px);
  c.cy = static_cast<float>(cam.cy_px);
  c.lim_x = 1.3f * static_cast<float>(0.5 * cam.width_px / cam.fx_px);
  c.lim_y = 1.3f * static_cast<float>(0.5 * cam.height_px / cam.fy_px);
  c.max_x = static_cast<float>(cam.width_px - 1);
  c.max_y = static_cast<float>(cam.height_px - 1);
  c.eps2d = eps2d_px2;
  return c;
}

}  // namespace vigs::mapping
