#include "tracking/organized_knn.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "tracking/knn_list.hpp"

namespace vigs::tracking {

OrganizedKnn::OrganizedKnn(int max_ring) : max_ring_(std::max(1, max_ring)) {
  for (int c = 0; c <= max_ring_; ++c) {
    const std::size_t first = offsets_.size();
    for (int dv = -c; dv <= c; ++dv) {
      for (int du = -c; du <= c; ++du) {
        if (std::max(std::abs(du), std::abs(dv)) == c) {
          offsets_.push_back({du, dv});
        }
      }
    }
    // Nearest cells of the ring first: the k-th distance, and so the pruning bound, drops
    // sooner and fewer candidates are inserted only to be displaced.
    std::stable_sort(offsets_.begin() + static_cast<std::ptrdiff_t>(first), offsets_.end(),
                     [](const Offset& a, const Offset& b) {
                       return a.du * a.du + a.dv * a.dv < b.du * b.du + b.dv * b.dv;
                     });
    ring_end_.push_back(static_cast<std::uint32_t>(offsets_.size()));
  }
}

int OrganizedKnn::knn(const PixelGrid& grid, const std::vector<Eigen::Vector3f>& points_m,
                      std::uint32_t i, int k, std::uint32_t* indices, float* sq_dists) const {
  const std::uint32_t cell = grid.cell_of[i];
  const int cu = static_cast<int>(cell % static_cast<std::uint32_t>(grid.width));
  const int cv = static_cast<int>(cell / static_cast<std::uint32_t>(grid.width));
  const Eigen::Vector3f& p = points_m[i];
  // Certificate terms, in double: the bound must not be rounded up.
  const double z = p.z();
  const double fx_h = grid.camera.fx_px * std::sqrt(double{p.x()} * p.x() + z * z);
  const double fy_h = grid.camera.fy_px * std::sqrt(double{p.y()} * p.y() + z * z);
  const double z2 = z * z;

  KnnList list;
  list.k = k;
  list.indices = indices;
  list.sq_dists = sq_dists;
  std::uint32_t o = 0;
  for (int c = 0; c <= max_ring_; ++c) {
    const bool inside = cu - c >= 0 && cu + c < grid.width && cv - c >= 0 && cv + c < grid.height;
    const std::uint32_t end = ring_end_[static_cast<std::size_t>(c)];
    for (; o < end; ++o) {
      const int u = cu + offsets_[o].du;
      const int v = cv + offsets_[o].dv;
      if (!inside && (u < 0 || u >= grid.width || v < 0 || v >= grid.height)) {
        continue;
      }
      const std::int32_t j = grid.point_at[static_cast<std::size_t>(v) * grid.width + u];
      if (j >= 0) {
        list.offer(static_cast<std::uint32_t>(j),
                   (points_m[static_cast<std::size_t>(j)] - p).squaredNorm());
      }
    }
    if (list.count == k) {
      // Closest any point of ring c + 1 or beyond can be (see the header).
      const double a = (c + 1) * grid.stride_px - 0.5;
      const double bound = std::min(a * z2 / (fx_h + a * z), a * z2 / (fy_h + a * z));
      if (double{list.worst} < bound * bound * (1.0 - 1e-6)) {
        return k;
      }
    }
  }
  return -1;
}

const OrganizedKnn& OrganizedKnn::shared() {
  static const OrganizedKnn instance;
  return instance;
}

int OrganizedKnn::nearest(const PixelGrid& grid, const std::vector<Eigen::Vector3f>& points_m,
                          const Eigen::Vector3f& q, float max_sq_dist, std::uint32_t hint,
                          std::uint32_t& index, float& sq_dist) const {
  const double z = q.z();
  if (!(z > 1e-6)) {
    return -1;
  }
  const PinholeCamera& cam = grid.camera;
  const double gu = (cam.fx_px * q.x() / z + cam.cx_px) / grid.stride_px;
  const double gv = (cam.fy_px * q.y() / z + cam.cy_px) / grid.stride_px;
  const double far = max_ring_ + 1.0;
  if (!(gu > -far && gu < grid.width - 1 + far && gv > -far && gv < grid.height - 1 + far)) {
    return -1;  // projects far outside the image (or NaN)
  }
  const int cu = static_cast<int>(std::lround(gu));
  const int cv = static_cast<int>(std::lround(gv));
  const double fx_h = cam.fx_px * std::sqrt(double{q.x()} * q.x() + z * z);
  const double fy_h = cam.fy_px * std::sqrt(double{q.y()} * q.y() + z * z);
  const double z2 = z * z;

  float best = max_sq_dist;
  bool found = false;
  if (hint < points_m.size()) {
    const float d2 = (points_m[hint] - q).squaredNorm();
    if (d2 < best) {
      best = d2;
      index = hint;
      found = true;
    }
  }
  std::uint32_t o = 0;
  for (int c = 0; c <= max_ring_; ++c) {
    const bool inside = cu - c >= 0 && cu + c < grid.width && cv - c >= 0 && cv + c < grid.height;
    const std::uint32_t end = ring_end_[static_cast<std::size_t>(c)];
    for (; o < end; ++o) {
      const int u = cu + offsets_[o].du;
      const int v = cv + offsets_[o].dv;
      if (!inside && (u < 0 || u >= grid.width || v < 0 || v >= grid.height)) {
        continue;
      }
      const std::int32_t j = grid.point_at[static_cast<std::size_t>(v) * grid.width + u];
      if (j < 0) {
        continue;
      }
      const float d2 = (points_m[static_cast<std::size_t>(j)] - q).squaredNorm();
      if (d2 < best) {
        best = d2;
        index = static_cast<std::uint32_t>(j);
        found = true;
      }
    }
    // Closest any point of ring c + 1 or beyond can be.
    const double a = (c + 0.5) * grid.stride_px - 0.01;
    const double bound = std::min(a * z2 / (fx_h + a * z), a * z2 / (fy_h + a * z));
    if (double{best} < bound * bound * (1.0 - 1e-6)) {
      if (found) {
        sq_dist = best;
      }
      return found ? 1 : 0;
    }
  }
  return -1;
}

}  // namespace vigs::tracking
