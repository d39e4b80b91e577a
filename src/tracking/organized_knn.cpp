#include "tracking/organized_knn.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "tracking/knn_list.hpp"

namespace vigs::tracking {

namespace {

// The certificate of the header: every point whose pixel lies at least a pixels (along u or
// v) from the projection of p is at least a z^2 / (f sqrt(x^2 + z^2) + a z) metres from p.
// In double, so the bound is not rounded up.
class DistanceBound {
 public:
  DistanceBound(const PinholeCamera& cam, const Eigen::Vector3f& p)
      : z_(p.z()),
        fx_h_(cam.fx_px * std::sqrt(double{p.x()} * p.x() + z_ * z_)),
        fy_h_(cam.fy_px * std::sqrt(double{p.y()} * p.y() + z_ * z_)) {}

  /// True when no point a_px pixels away or more can be closer than sqrt(sq_dist) (with a
  /// 1e-6 relative margin for the float distances).
  [[nodiscard]] bool excludes(float sq_dist, double a_px) const {
    const double z2 = z_ * z_;
    const double r = std::min(a_px * z2 / (fx_h_ + a_px * z_), a_px * z2 / (fy_h_ + a_px * z_));
    return double{sq_dist} < r * r * (1.0 - 1e-6);
  }

 private:
  double z_, fx_h_, fy_h_;
};

}  // namespace

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
  const DistanceBound bound(grid.camera, p);

  KnnList list;
  list.k = k;
  list.indices = indices;
  list.sq_dists = sq_dists;
  for (int c = 0; c <= max_ring_; ++c) {
    for_each_in_ring(grid, cu, cv, c,
                     [&](std::uint32_t j) { list.offer(j, (points_m[j] - p).squaredNorm()); });
    // Grid points project exactly on their cells: ring c + 1 is >= (c + 1) * stride pixels
    // away (0.5 px margin for rounding).
    if (list.count == k && bound.excludes(list.worst, (c + 1) * grid.stride_px - 0.5)) {
      return k;
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
  const DistanceBound bound(cam, q);

  // Locals, not the out-parameters, inside the loop: a store through `index` could alias the
  // grid's int32 cells and force reloads.
  float best = max_sq_dist;
  std::uint32_t best_index = 0;
  bool found = false;
  if (hint < points_m.size()) {
    const float d2 = (points_m[hint] - q).squaredNorm();
    if (d2 < best) {
      best = d2;
      best_index = hint;
      found = true;
    }
  }
  for (int c = 0; c <= max_ring_; ++c) {
    for_each_in_ring(grid, cu, cv, c, [&](std::uint32_t j) {
      const float d2 = (points_m[j] - q).squaredNorm();
      if (d2 < best) {
        best = d2;
        best_index = j;
        found = true;
      }
    });
    // q lies within half a cell of (cu, cv): ring c + 1 is >= (c + 0.5) * stride pixels from
    // its projection (0.01 px margin for rounding).
    if (bound.excludes(best, (c + 0.5) * grid.stride_px - 0.01)) {
      if (found) {
        index = best_index;
        sq_dist = best;
      }
      return found ? 1 : 0;
    }
  }
  return -1;
}

}  // namespace vigs::tracking
