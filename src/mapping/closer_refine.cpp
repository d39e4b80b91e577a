#include "mapping/closer_refine.hpp"

#include <algorithm>
#include <cmath>

namespace vigs::mapping {

namespace {

std::size_t condemn_range(const GaussianMap& map, const RenderCamera& cam, const float* depth_m,
                          double sample_angle_rad, const config::InsertSettings& insert,
                          const CloserRefineSettings& s, std::size_t lo, std::size_t hi,
                          std::vector<char>& keep) {
  const int w = cam.width_px, h = cam.height_px;
  const double* R = cam.R_c_w;
  const double* t = cam.t_c_w;
  const double f_px = std::max(cam.fx_px, cam.fy_px);
  std::size_t condemned = 0;
  for (std::size_t i = lo; i < hi; ++i) {
    if (map.opacity_logit[i] <= kRemovedLogit) continue;  // removed, awaiting compaction
    const float* m = &map.mean_w[3 * i];
    const double z = R[6] * m[0] + R[7] * m[1] + R[8] * m[2] + t[2];
    if (!(z > 1e-3)) continue;
    const float* ls = &map.log_scale[3 * i];
    const float lo_s = std::min({ls[0], ls[1], ls[2]}), hi_s = std::max({ls[0], ls[1], ls[2]});
    const double mid_sd = std::exp(static_cast<double>(ls[0] + ls[1] + ls[2] - lo_s - hi_s));
    const double fine_sd = insert.cover * std::max(z * sample_angle_rad, insert.voxel_m);
    if (!(mid_sd > s.ratio * fine_sd)) continue;
    const double x = R[0] * m[0] + R[1] * m[1] + R[2] * m[2] + t[0];
    const double y = R[3] * m[0] + R[4] * m[1] + R[5] * m[2] + t[1];
    const double u = cam.fx_px * x / z + cam.cx_px, v = cam.fy_px * y / z + cam.cy_px;
    const double r_px = 2.0 * f_px * std::exp(static_cast<double>(hi_s)) / z;
    if (!(u - r_px >= 0.0 && v - r_px >= 0.0 && u + r_px <= w - 1 && v + r_px <= h - 1)) continue;
    const auto at = [&](double uu, double vv) {
      return depth_m[static_cast<std::size_t>(std::lround(vv)) * w + std::lround(uu)];
    };
    const float d = at(u, v);
    if (!(d > 0.0f) || std::abs(d - z) > s.depth_rel * d) continue;
    // the footprint's ends have depth too: the keyframe's samples can refill all of it (a
    // footprint over the edge of the depth range or a moving object would leave a hole)
    if (!(at(u - r_px, v) > 0.0f && at(u + r_px, v) > 0.0f && at(u, v - r_px) > 0.0f &&
          at(u, v + r_px) > 0.0f))
      continue;
    keep[i] = 0;
    ++condemned;
  }
  return condemned;
}

}  // namespace

std::size_t condemn_seen_closer(const GaussianMap& map, const RenderCamera& cam,
                                const float* depth_m, double sample_angle_rad,
                                const config::InsertSettings& insert, const CloserRefineSettings& s,
                                std::vector<char>& keep, MapBlocks* blocks) {
  const std::size_t n = map.size();
  keep.assign(n, 1);
  if (!(s.ratio > 0.0) || !(sample_angle_rad > 0.0) || !depth_m || cam.width_px < 1 ||
      cam.height_px < 1)
    return 0;
  // the rule looks only at means inside the image in front of the camera (z > 1 mm)
  std::size_t condemned = 0;
  for_ranges_in_view(map, cam, blocks, [&](std::size_t lo, std::size_t hi) {
    condemned += condemn_range(map, cam, depth_m, sample_angle_rad, insert, s, lo, hi, keep);
  });
  return condemned;
}

}  // namespace vigs::mapping
