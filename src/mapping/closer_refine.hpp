#pragma once
// Refinement when a surface is seen from closer: a Gaussian is inserted the size of its
// sample's footprint at the depth it was first seen from (insertion.hpp), so a wall inserted
// 10 m down a corridor is made of 7 cm Gaussians, and when the camera later passes it at 1.5 m
// the map renders it blurred. The insertion gate cannot fix that: the blurred render is near
// the new keyframe's patch means, and a finer Gaussian added behind or beside a coarse one is
// hidden by it about half the time (BENCHMARKS.md, the twelfth session's experiment).
//
// Rule: when a keyframe arrives, every Gaussian's centre is projected into it. The Gaussian is
// replaced (marked removed here; the keyframe's own samples then fill the hole through the
// insertion gate, which finds the map missing there) when all of these hold:
// - it lies on the surface the keyframe measured: the centre pixel's depth d > 0 (not missing,
//   not a moving object's) and |d - z| <= depth_rel * d, with z the Gaussian's camera depth;
// - its whole footprint is in the image and measured: its centre is at least 2 projected
//   standard deviations (the largest) from every border, and the four pixels that far to its
//   left, right, top and bottom have depth (not missing, not moving), so the keyframe's samples
//   can refill what it covered;
// - it is coarse for this view: its middle standard deviation (in-plane and unstretched by a
//   slant, insertion.hpp) exceeds ratio times what the keyframe's own sample at depth z gets,
//   cover * max(z * sample_angle, voxel).
// A revisit from the same distance replaces nothing; the voxel floor bounds how often a surface
// can be refined. One pass over the Gaussians the camera may see (MapBlocks), no allocation.
#include <cstddef>
#include <vector>

#include "core/config/mapping_components.hpp"
#include "mapping/gaussian_map.hpp"
#include "mapping/map_blocks.hpp"
#include "mapping/render_camera.hpp"

namespace vigs::mapping {

using config::CloserRefineSettings;  // defaults: core/config/mapping_components.hpp

/// keep[i] = 0 for the Gaussians of `map` that the keyframe (camera `cam`, depth_m 1 per pixel:
/// > 0 measured, 0 missing, < 0 moving; samples every `sample_angle_rad`, inserted with
/// `insert`'s cover and voxel) sees from closer than their size stands for; returns how many.
/// Gaussians already removed (kRemovedLogit) are skipped. With `blocks` (brought up to date
/// here) only blocks the camera may see are visited; the result is the same.
std::size_t condemn_seen_closer(const GaussianMap& map, const RenderCamera& cam,
                                const float* depth_m, double sample_angle_rad,
                                const config::InsertSettings& insert, const CloserRefineSettings& s,
                                std::vector<char>& keep, MapBlocks* blocks = nullptr);

}  // namespace vigs::mapping
