#pragma once
// See-through pruning: a Gaussian that later keyframes see through is not a surface. When a
// keyframe arrives, every Gaussian's centre is projected into it; where the keyframe measured
// depth around that pixel, the keyframe votes:
// - "through" when every depth of the pixel's 3x3 neighbourhood lies behind the Gaussian by
//   more than margin_m + margin_per_m * z (z the Gaussian's depth): the keyframe saw a surface
//   behind free space where the Gaussian is (a person who stood there for a moment, a Gaussian
//   inserted before the tracker recognised the person as moving). With missing_far a pixel
//   without depth counts as behind (beyond the range: a corridor's end, as the far field takes
//   it), except for the far field's own Gaussians (the `far` flags), which stand for "no
//   depth" and which such a pixel agrees with;
// - "seen" when the centre pixel's depth is within that margin of the Gaussian's (or missing,
//   for a far-field Gaussian);
// - nothing when the Gaussian is hidden (a surface in front of it), outside the image, near a
//   moving object's pixel (negative depth, pipeline/moving_pixels.hpp) or, without
//   missing_far, near a pixel without depth.
// A Gaussian seen through by at least min_count keyframes, and by at least min_fraction of the
// keyframes that voted on it, is pruned. With max_age_keyframes only keyframes soon after the
// one that inserted a Gaussian vote on it: a person is seen through within seconds, while a
// revisit minutes later sees the place from a pose that carries the drift accumulated between
// (tens of centimetres before a loop closes), which would condemn static surfaces that only
// the inserting keyframe and the revisit ever saw (the floor at a run's start). The neighbourhood
// test keeps depth edges from voting through the thin Gaussians along them. Counts are two
// saturating 16-bit numbers per Gaussian (4 bytes), kept aligned with the map through compact()
// after any other pruning; the far flags are the caller's (the Mapper keeps them with the map). One
// pass over the Gaussians per keyframe, no allocation per Gaussian.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/config/mapping_components.hpp"
#include "mapping/gaussian_map.hpp"
#include "mapping/map_blocks.hpp"
#include "mapping/render_camera.hpp"

namespace vigs::mapping {

using config::SeeThroughSettings;  // defaults: core/config/mapping_components.hpp

class SeeThrough {
 public:
  explicit SeeThrough(SeeThroughSettings s = {}) : s_(s) {}

  /// Votes of one keyframe (camera `cam`, depth_m 1 per pixel: > 0 measured, 0 missing, < 0
  /// moving) for every Gaussian of `map`. Gaussians appended to the map since the last call
  /// start with no votes. keep[i] = 0 for the Gaussians to prune now (their votes meet the
  /// rule); returns how many. The caller removes them from the map and calls compact(keep),
  /// or marks them removed (opacity logit kRemovedLogit: they no longer vote) and compacts
  /// later. With `blocks` (brought up to date with `map` here) only blocks the camera may see
  /// are visited; the votes are the same.
  /// With `anchor` (one keyframe id per Gaussian, the keyframe that inserted it) and
  /// max_age_keyframes > 0, keyframe `voter_id` votes only on Gaussians inserted at most
  /// max_age_keyframes keyframes before it. `far` (one per Gaussian, non-zero for the far
  /// field's Gaussians; null: none is) says which stand for "no depth".
  std::size_t vote(const GaussianMap& map, const RenderCamera& cam, const float* depth_m,
                   std::vector<char>& keep, MapBlocks* blocks = nullptr,
                   const std::uint32_t* anchor = nullptr, std::uint32_t voter_id = 0,
                   const std::uint8_t* far = nullptr);

  /// Keeps the counts of the Gaussians whose keep[i] is non-zero, as GaussianParams::compact.
  void compact(const std::vector<char>& keep);

  [[nodiscard]] std::uint16_t through(std::size_t i) const { return through_[i]; }
  [[nodiscard]] std::uint16_t seen(std::size_t i) const { return seen_[i]; }
  [[nodiscard]] std::size_t size() const { return through_.size(); }
  /// Bytes held (capacity of the counts).
  [[nodiscard]] std::size_t bytes() const {
    return (through_.capacity() + seen_.capacity()) * sizeof(std::uint16_t);
  }
  [[nodiscard]] const SeeThroughSettings& settings() const { return s_; }

 private:
  std::size_t vote_range(const GaussianMap& map, const RenderCamera& cam, const float* depth_m,
                         std::size_t lo, std::size_t hi, std::vector<char>& keep,
                         const std::uint32_t* anchor, std::uint32_t voter_id,
                         const std::uint8_t* far_flags);
  SeeThroughSettings s_;
  std::vector<std::uint16_t> through_, seen_;
};

}  // namespace vigs::mapping
