#include "mapping/far_field.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

namespace vigs::mapping {

std::size_t insert_far_field(GaussianMap& map, const FarFieldView& view,
                             const RenderResult<float>* render, const FarFieldSettings& s,
                             double cover, double opacity, double max_alpha, double max_sd_m) {
  const RenderCamera& cam = view.camera;
  if (!(s.depth_m > 0.0) || s.stride_px < 1 || !view.rgb || cam.width_px <= 0) return 0;
  const int st = s.stride_px, w = cam.width_px, h = cam.height_px;
  // the gating render is at the view's resolution or at half of it (half_res_view.hpp)
  int down = 0;
  if (render && render->width == w && render->height == h) down = 1;
  if (render && render->width == w / 2 && render->height == h / 2 && w >= 2 && h >= 2) down = 2;
  const bool gated = down > 0;
  // the plane comes closer where the footprint at depth_m would need more than max_sd_m
  const double footprint_rad = cover * st / std::min(cam.fx_px, cam.fy_px);
  const double z = std::min(s.depth_m, max_sd_m / footprint_rad);
  // a disc in the plane z = depth_m: axes along the camera's x and y, normal along its z
  const Eigen::Matrix3d R_w_c =
      Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(cam.R_c_w).transpose();
  const Eigen::Vector3d t_c_w(cam.t_c_w[0], cam.t_c_w[1], cam.t_c_w[2]);
  const Eigen::Quaterniond q_w(R_w_c);
  const float quat[4] = {static_cast<float>(q_w.w()), static_cast<float>(q_w.x()),
                         static_cast<float>(q_w.y()), static_cast<float>(q_w.z())};
  const double sd_x = cover * z * st / cam.fx_px;
  const double sd_y = cover * z * st / cam.fy_px;
  const float log_s[3] = {static_cast<float>(std::log(sd_x)), static_cast<float>(std::log(sd_y)),
                          static_cast<float>(std::log(0.1 * std::min(sd_x, sd_y)))};
  const double op = std::clamp(opacity, 0.01, 0.99);
  const float logit = static_cast<float>(std::log(op / (1.0 - op)));
  // a negative depth marks a moving object's pixel: not "no depth, far away" (no colour is
  // taken from it), but what lies behind it is unknown, so it does not keep a block whose other
  // pixels have no depth from its far Gaussian (a person before a corridor's far end)
  auto missing = [&](std::size_t p) {
    return !view.depth_m || !(std::isfinite(view.depth_m[p]) && view.depth_m[p] != 0.0f);
  };
  auto moving = [&](std::size_t p) { return view.depth_m && view.depth_m[p] < 0.0f; };
  std::size_t added = 0;
  for (int v0 = 0; v0 < h; v0 += st) {
    for (int u0 = 0; u0 < w; u0 += st) {
      const int u1 = std::min(w, u0 + st), v1 = std::min(h, v0 + st);
      double rgb[3] = {0, 0, 0}, alpha = 0;
      int n = 0, n_moving = 0;
      for (int v = v0; v < v1; ++v) {
        for (int u = u0; u < u1; ++u) {
          const std::size_t p = static_cast<std::size_t>(v) * w + u;
          if (moving(p)) ++n_moving;
          if (!missing(p)) continue;
          for (int c = 0; c < 3; ++c) rgb[c] += view.rgb[3 * p + c];
          if (gated)
            alpha += render->alpha(std::min(v / down, render->height - 1) * render->width +
                                   std::min(u / down, render->width - 1));
          ++n;
        }
      }
      if (n == 0 || 2 * (n + n_moving) < (u1 - u0) * (v1 - v0)) continue;
      if (gated && alpha > max_alpha * op * n) continue;
      // the block's centre (pixel centres at integer coordinates)
      const double uc = 0.5 * (u0 + u1 - 1), vc = 0.5 * (v0 + v1 - 1);
      const Eigen::Vector3d p_c((uc - cam.cx_px) / cam.fx_px * z, (vc - cam.cy_px) / cam.fy_px * z,
                                z);
      const Eigen::Vector3d p_w = R_w_c * (p_c - t_c_w);
      const float mean[3] = {static_cast<float>(p_w.x()), static_cast<float>(p_w.y()),
                             static_cast<float>(p_w.z())};
      const float col[3] = {static_cast<float>(rgb[0] / n), static_cast<float>(rgb[1] / n),
                            static_cast<float>(rgb[2] / n)};
      map.push_back(mean, log_s, quat, logit, col);
      ++added;
    }
  }
  return added;
}

}  // namespace vigs::mapping
