#pragma once
// Exact k-nearest-neighbour search among the points of one depth image, through the image
// (the idea of PCL's OrganizedNeighbor, written here for this project). Cells of the pixel grid
// are visited in square rings of growing Chebyshev radius around the query's cell, nearest
// first, and the search stops as soon as no point in an unvisited ring can be closer than the
// k-th found so far. The stopping rule is a certificate, not a heuristic: a point q whose pixel
// lies a >= 0 pixels from the query p = (x, y, z)'s pixel along u satisfies
//     |q - p| >= a z^2 / (fx sqrt(x^2 + z^2) + a z)
// (from |du| = fx |z dx - x dz| / (z (z + dz)) <= fx sqrt(x^2 + z^2) r / (z (z - r)) for
// |q - p| <= r < z), and likewise along v; ring c + 1 is at least (c + 1) * stride - 0.5 pixels
// away in u or v. So the result equals a kd-tree's up to the order of equidistant points.
// When no certificate is reached within max_ring rings (isolated points, points at the image
// border with few neighbours), knn() returns -1 and the caller falls back to a kd-tree.
//
// nearest() answers the same question for any query point in the camera frame (a GICP
// correspondence): its projection's cell is the centre, and a cell c + 1 rings out is at least
// (c + 0.5) * stride - 0.01 pixels from the projection.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "tracking/pixel_grid.hpp"

namespace vigs::tracking {

class OrganizedKnn {
 public:
  static constexpr int kDefaultMaxRing = 10;

  /// Precomputes the ring offsets (allocates); knn() does not allocate.
  explicit OrganizedKnn(int max_ring = kDefaultMaxRing);

  /// The k nearest points to point i of the cloud `grid` describes, nearest first (the point
  /// itself included, at distance 0); original indices and squared distances (m^2). Returns k,
  /// or -1 when not certified within max_ring rings (or the cloud has fewer than k points).
  int knn(const PixelGrid& grid, const std::vector<Eigen::Vector3f>& points_m, std::uint32_t i,
          int k, std::uint32_t* indices, float* sq_dists) const;

  /// Nearest point of the cloud `grid` describes to q (camera frame, metres) strictly within
  /// sqrt(max_sq_dist): 1 (index, sq_dist set), 0 when certainly none, -1 when not certified
  /// (q behind the camera or projecting far outside the image, or max_ring rings not enough).
  /// `hint` (a point index, or 0xffffffff) is tried first to tighten the bound.
  int nearest(const PixelGrid& grid, const std::vector<Eigen::Vector3f>& points_m,
              const Eigen::Vector3f& q, float max_sq_dist, std::uint32_t hint, std::uint32_t& index,
              float& sq_dist) const;

  [[nodiscard]] int max_ring() const { return max_ring_; }
  /// An instance with the default ring count, built once (for GICP targets).
  static const OrganizedKnn& shared();

 private:
  struct Offset {
    std::int32_t du, dv;
  };
  /// Calls visit(point index) for every point in ring c (Chebyshev radius in cells) around
  /// cell (cu, cv), nearest cells first; cells outside the grid are skipped.
  template <class Visit>
  void for_each_in_ring(const PixelGrid& grid, int cu, int cv, int c, Visit&& visit) const {
    const bool inside = cu - c >= 0 && cu + c < grid.width && cv - c >= 0 && cv + c < grid.height;
    const std::uint32_t end = ring_end_[static_cast<std::size_t>(c)];
    for (std::uint32_t o = c == 0 ? 0u : ring_end_[static_cast<std::size_t>(c) - 1]; o < end; ++o) {
      const int u = cu + offsets_[o].du;
      const int v = cv + offsets_[o].dv;
      if (!inside && (u < 0 || u >= grid.width || v < 0 || v >= grid.height)) {
        continue;
      }
      const std::int32_t j =
          grid.point_at[static_cast<std::size_t>(v) * static_cast<std::size_t>(grid.width) +
                        static_cast<std::size_t>(u)];
      if (j >= 0) {
        visit(static_cast<std::uint32_t>(j));
      }
    }
  }
  int max_ring_;
  std::vector<Offset> offsets_;          ///< ring by ring; within a ring by distance
  std::vector<std::uint32_t> ring_end_;  ///< offsets_[ring_end_[c - 1], ring_end_[c]) is ring c
};

}  // namespace vigs::tracking
