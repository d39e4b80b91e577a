#pragma once
// Where each point of an organised cloud came from: the grid of sampled pixels of its depth
// image (every stride-th pixel from (0, 0)), the point at each cell and the cell of each point,
// with the intrinsics used to back-project them. DepthToPoints fills it; OrganizedKnn searches
// neighbours through it. It describes the cloud only while the cloud is not reordered or
// resampled (voxel averaging clears it).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/types/pinhole_camera.hpp"

namespace vigs::tracking {

struct PixelGrid {
  int width = 0;      ///< cells per row (sampled pixels)
  int height = 0;     ///< rows of cells
  int stride_px = 1;  ///< pixels between neighbouring cells
  PinholeCamera camera;
  std::vector<std::int32_t> point_at;  ///< cell (row-major) -> point index, -1 when none
  std::vector<std::uint32_t> cell_of;  ///< point index -> cell

  /// True when the grid describes a cloud of `num_points` points.
  [[nodiscard]] bool describes(std::size_t num_points) const {
    return num_points > 0 && cell_of.size() == num_points &&
           point_at.size() == static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
  /// Keeps capacity, so a reused grid does not allocate once warmed up.
  void clear() {
    width = height = 0;
    point_at.clear();
    cell_of.clear();
  }
};

}  // namespace vigs::tracking
