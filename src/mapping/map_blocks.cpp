#include "mapping/map_blocks.hpp"

#include <algorithm>
#include <cmath>

namespace vigs::mapping {

void MapBlocks::compute(const GaussianMap& map, std::size_t b) {
  const std::size_t begin = b * kBlock, end = std::min(map.size(), begin + kBlock);
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  float max_log_scale = -INFINITY;
  bool finite = true;
  for (std::size_t i = begin; i < end; ++i) {
    const float* m = &map.mean_w[3 * i];
    for (int k = 0; k < 3; ++k) {
      finite = finite && std::isfinite(m[k]);
      lo[k] = std::min(lo[k], double{m[k]});
      hi[k] = std::max(hi[k], double{m[k]});
    }
    const float* ls = &map.log_scale[3 * i];
    max_log_scale = std::max({max_log_scale, ls[0], ls[1], ls[2]});
    finite = finite && !std::isnan(ls[0]) && !std::isnan(ls[1]) && !std::isnan(ls[2]);
  }
  Bound& out = bounds_[b];
  if (!finite) {  // a block holding a bad Gaussian is never culled
    out.radius_m = INFINITY;
    return;
  }
  double r2 = 0;
  for (int k = 0; k < 3; ++k) out.center_w[k] = 0.5 * (lo[k] + hi[k]);
  for (std::size_t i = begin; i < end; ++i) {
    const float* m = &map.mean_w[3 * i];
    double d2 = 0;
    for (int k = 0; k < 3; ++k) d2 += (m[k] - out.center_w[k]) * (m[k] - out.center_w[k]);
    r2 = std::max(r2, d2);
  }
  // a little slack for the float arithmetic of the per-Gaussian cull
  out.radius_m = std::sqrt(r2) * (1.0 + 1e-6) + 1e-6;
  out.sigma_m = std::exp(double{max_log_scale}) * 1.001;
}

void MapBlocks::update(const GaussianMap& map, rt::WorkerTeam* team) {
  const std::size_t n = map.size();
  const std::size_t nb = (n + kBlock - 1) / kBlock;
  std::size_t first_new = n_ / kBlock;  // the block that held the old end may have grown
  if (!valid_ || n < n_) first_new = 0;
  bounds_.resize(nb);
  dirty_.resize(nb, 0);
  todo_.clear();
  for (std::size_t b = 0; b < std::min(first_new, nb); ++b)
    if (any_dirty_ && dirty_[b]) todo_.push_back(b);
  for (std::size_t b = first_new; b < nb; ++b) todo_.push_back(b);
  if (team && todo_.size() > 1) {
    team->run_claimed(todo_.size(), [&](int, std::size_t k) { compute(map, todo_[k]); });
  } else {
    for (const std::size_t b : todo_) compute(map, b);
  }
  std::fill(dirty_.begin(), dirty_.end(), 0);
  any_dirty_ = false;
  n_ = n;
  valid_ = true;
}

void MapBlocks::mark_changed(const std::vector<int>& ids) {
  for (const int id : ids) {
    const auto b = static_cast<std::size_t>(id) / kBlock;
    if (b < dirty_.size()) dirty_[b] = 1;  // later ids are appended ones: update() takes them
  }
  any_dirty_ = any_dirty_ || !ids.empty();
}

// project_gaussian() keeps a Gaussian (mean p in the camera, largest standard deviation s) only
// if z > near and, for the right image edge, u - r <= W - 1 with u = fx x / z + cx and
// r = ceil(3 sqrt(j2 s^2 + eps2d + 0.32)), j2 <= G^2 / z^2, G^2 = fx^2 (1 + lx^2) +
// fy^2 (1 + ly^2) (lx, ly: its clamps of x/z and y/z). With r <= 3 G s / z + P,
// P = 3 sqrt(eps2d + 0.32) + 1, and z > 0 that gives x - a z <= 3 G s / fx with
// a = (W - 1 + P - cx) / fx: the mean lies within 3 G s / fx of the half-space behind the plane
// x = a z. A block whose means lie within radius of its centre is culled when the centre lies
// farther than radius + 3 G sigma / fx in front of that plane; likewise for the other edges.
bool MapBlocks::may_be_visible(std::size_t b, const RenderCamera& cam,
                               const RasterSettings& rs) const {
  const Bound& bd = bounds_[b];
  if (!(bd.radius_m < INFINITY)) return true;
  const double* R = cam.R_c_w;
  const double* t = cam.t_c_w;
  const double* c = bd.center_w;
  const double x = R[0] * c[0] + R[1] * c[1] + R[2] * c[2] + t[0];
  const double y = R[3] * c[0] + R[4] * c[1] + R[5] * c[2] + t[1];
  const double z = R[6] * c[0] + R[7] * c[1] + R[8] * c[2] + t[2];
  if (z + bd.radius_m <= rs.near_m) return false;
  const double lx = 1.3 * 0.5 * cam.width_px / cam.fx_px;
  const double ly = 1.3 * 0.5 * cam.height_px / cam.fy_px;
  const double g =
      std::sqrt(cam.fx_px * cam.fx_px * (1 + lx * lx) + cam.fy_px * cam.fy_px * (1 + ly * ly));
  const double p =
      3.0 * std::sqrt(cam.lowpass_px2(rs.eps2d_px2) + 0.32) + 1.0 + 2.0;  // + 2 px of slack
  auto outside = [&](double along, double slope, double f) {
    // plane along = slope * z, unit normal (1, -slope) / sqrt(1 + slope^2) in (along, z)
    const double dist = (along - slope * z) / std::sqrt(1.0 + slope * slope);
    return dist > bd.radius_m + 3.0 * g * bd.sigma_m / f;
  };
  return !(outside(x, (cam.width_px - 1 + p - cam.cx_px) / cam.fx_px, cam.fx_px) ||
           outside(-x, (cam.cx_px + p) / cam.fx_px, cam.fx_px) ||
           outside(y, (cam.height_px - 1 + p - cam.cy_px) / cam.fy_px, cam.fy_px) ||
           outside(-y, (cam.cy_px + p) / cam.fy_px, cam.fy_px));
}

}  // namespace vigs::mapping
