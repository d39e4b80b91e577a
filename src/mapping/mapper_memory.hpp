#pragma once
// What the mapper holds, in bytes, by owner (mapping::Mapper::memory()): every container that
// grows with the map, from vector capacities (what was asked of the allocator, not what malloc
// adds per block), so a figure reads the same on every run of the same schedule. Per Gaussian:
// the map's parameters, Adam's moments, the rasterizer's caches (projection, tile lists, the
// per-pair gradients, the prune mask), the inserter's voxel occupancy
// and the see-through counts. Beside those: the keyframes the mapper keeps for training (their
// images and depth; their points are dropped once inserted), the last published snapshot (a
// copy of the map, shared with its readers) and the per-pixel buffers of the optimiser's and
// the gate's renders. Not counted: the photometric loss's own per-pixel scratch, the keyframe
// ring (the pipeline's), the tracker.
#include <cstddef>

namespace vigs::mapping {

struct MapperMemory {
  std::size_t gaussians = 0;           ///< map size when measured
  std::size_t map_params_bytes = 0;    ///< GaussianMap parameter arrays, anchors and far flags
  std::size_t adam_moments_bytes = 0;  ///< Adam first and second moments, last step per Gaussian
  /// The optimiser's rasterizer caches: projection, tile lists, per-pair gradients
  /// (not the per-thread tile scratch), and the optimiser's prune mask.
  std::size_t optimizer_buffers_bytes = 0;
  /// GaussianInserter's voxel occupancy: its hash table's slots (a brick key, a mask and a
  /// control byte each; voxel_occupancy.hpp).
  std::size_t occupancy_bytes = 0;
  std::size_t see_through_bytes = 0;   ///< vote counts and the removal keep mask
  std::size_t keyframes_bytes = 0;     ///< held keyframes: images, depth, points not yet inserted
  std::size_t snapshot_bytes = 0;      ///< the last published snapshot (0 when none)
  std::size_t view_buffers_bytes = 0;  ///< per-pixel: renders, loss gradients, gate mask

  /// The owners whose bytes grow with the number of Gaussians.
  [[nodiscard]] std::size_t per_gaussian_owners_bytes() const {
    return map_params_bytes + adam_moments_bytes + optimizer_buffers_bytes + occupancy_bytes +
           see_through_bytes;
  }
  [[nodiscard]] std::size_t total_bytes() const {
    return per_gaussian_owners_bytes() + keyframes_bytes + snapshot_bytes + view_buffers_bytes;
  }
  /// per_gaussian_owners_bytes() / gaussians (0 for an empty map).
  [[nodiscard]] double bytes_per_gaussian() const {
    return gaussians == 0
               ? 0.0
               : static_cast<double>(per_gaussian_owners_bytes()) / static_cast<double>(gaussians);
  }
};

}  // namespace vigs::mapping
