#pragma once
// Bounds of consecutive blocks of Gaussians, so that a view skips whole blocks it cannot see.
// Insertion appends one keyframe's points together, so a block of neighbours in the map's order
// is compact in space; on the live office the camera sees a few hundred thousand of four million
// Gaussians, and without the blocks every forward pass (each optimiser iteration and each
// keyframe's insertion gate) projects all of them.
//
// The cull is conservative with respect to project_gaussian()'s own early cull: a block is
// skipped only when, by the bound derived in may_be_visible(), no Gaussian in it could pass that
// cull, so a forward pass renders exactly the same with the blocks as without them.
//
// Keeping the bounds true is the owner's job: mark_changed() for Gaussians whose mean or scale
// changed (the optimiser's step), invalidate() after a compaction. Appends are found by size.
#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

#include "core/capacity_bytes.hpp"
#include "mapping/gaussian_map.hpp"
#include "mapping/raster_settings.hpp"
#include "mapping/render_camera.hpp"
#include "rt/worker_team.hpp"

namespace vigs::mapping {

class MapBlocks {
 public:
  static constexpr std::size_t kBlock = 1024;  ///< Gaussians per block

  /// Brings the bounds up to date with `map`: blocks marked changed, blocks past the last
  /// update's size (appended), or all of them after invalidate() or when the map shrank. With
  /// `team` its members claim the blocks (each block's bound is its own, so the bounds are the
  /// same): after a prune's compaction every block of a map of a million is recomputed.
  void update(const GaussianMap& map, rt::WorkerTeam* team = nullptr);
  /// Gaussians whose mean or scale changed since the last update (any order).
  void mark_changed(const std::vector<int>& ids);
  /// Everything is recomputed at the next update (after a compaction or a load).
  void invalidate() { valid_ = false; }

  /// False when no Gaussian of block b can pass project_gaussian()'s cull for `cam` (the
  /// bounds must be up to date).
  [[nodiscard]] bool may_be_visible(std::size_t b, const RenderCamera& cam,
                                    const RasterSettings& rs) const;
  [[nodiscard]] std::size_t blocks() const { return bounds_.size(); }
  /// [begin, end) of the Gaussians in block b (as of the last update).
  [[nodiscard]] std::pair<std::size_t, std::size_t> range(std::size_t b) const {
    const std::size_t begin = b * kBlock;
    return {begin, std::min(n_, begin + kBlock)};
  }
  [[nodiscard]] std::size_t gaussians() const { return n_; }
  [[nodiscard]] std::size_t bytes() const { return capacity_bytes(bounds_, dirty_, todo_); }

 private:
  struct Bound {
    double center_w[3] = {0, 0, 0};
    double radius_m = 0;  ///< of the means about the centre
    double sigma_m = 0;   ///< largest standard deviation in the block
  };
  void compute(const GaussianMap& map, std::size_t b);

  std::vector<Bound> bounds_;
  std::vector<char> dirty_;        ///< per block
  std::vector<std::size_t> todo_;  ///< the blocks an update recomputes
  std::size_t n_ = 0;              ///< map size at the last update
  bool valid_ = false;
  bool any_dirty_ = false;
};

/// Runs fn(begin, end) over the Gaussians of `map` whose mean may lie in front of `cam` (z > 0)
/// and inside its image: with `blocks` (brought up to date with `map` here) only the blocks whose
/// bound allows that, without them all of [0, map.size()). For rules that look only at the pixel
/// of a Gaussian's mean (see_through.hpp, closer_refine.hpp): the blocks' cull is the
/// rasterizer's, which keeps every block with such a mean, so the result is the same.
template <class Fn>
void for_ranges_in_view(const GaussianMap& map, const RenderCamera& cam, MapBlocks* blocks,
                        Fn&& fn) {
  if (!blocks) {
    fn(std::size_t{0}, map.size());
    return;
  }
  RasterSettings rs;
  rs.near_m = 0.0;
  blocks->update(map);
  for (std::size_t b = 0; b < blocks->blocks(); ++b) {
    if (!blocks->may_be_visible(b, cam, rs)) continue;
    const auto [lo, hi] = blocks->range(b);
    fn(lo, hi);
  }
}

}  // namespace vigs::mapping
