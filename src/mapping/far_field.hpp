#pragma once
// Far field: what lies beyond the depth range (or has no valid depth: sky through a window,
// a corridor's far end, the border a depth camera leaves black) gets sparse "far" Gaussians so
// that it does not render black. The image is cut into stride x stride pixel blocks; a block
// where at least half of the pixels have no depth, and where the map's render from the same
// camera is still mostly empty (mean accumulated opacity over those pixels below max_alpha times
// the far Gaussians' opacity, which a far Gaussian alone reaches), gets
// one Gaussian on the ray through the block's centre at camera depth z = depth_m. It is a disc
// facing the camera (the plane z = depth_m is tiled exactly by the blocks), its in-plane standard
// deviations cover x the block's footprint there (depth_m * stride / f), its thickness a tenth of
// that, its opacity the insertion's full-confidence opacity and its colour the mean of the block's
// pixels without depth. Where that standard deviation would exceed max_sd_m (below the pruning
// bound) the plane comes closer, to the depth where it does not: sparse far Gaussians must not
// leave holes between them.
// Being gated by the render, a revisit adds far Gaussians only where the map is still empty.
// Pixels of moving objects (negative depth, pipeline/moving_pixels.hpp) give no colour (a
// person's pixel is not far away), but count with the pixels without depth towards the block's
// half: what lies behind a person is unknown, and a person before a corridor's far end must not
// leave the block black.
#include <cstddef>

#include "core/config/mapping_components.hpp"
#include "mapping/gaussian_map.hpp"
#include "mapping/rasterizer.hpp"
#include "mapping/render_camera.hpp"

namespace vigs::mapping {

using config::FarFieldSettings;  // defaults: core/config/mapping_components.hpp

struct FarFieldView {
  RenderCamera camera;
  const float* rgb = nullptr;      ///< 3 per pixel, [0, 1]
  const float* depth_m = nullptr;  ///< 1 per pixel, 0 (or not finite) = missing, < 0 = moving
};

/// Appends the view's far Gaussians to `map`; returns how many. `render` (the map rendered from
/// view.camera, at its resolution or at half_res_camera(); null = the map is empty there) gates
/// them. Does nothing when s.depth_m <= 0.
std::size_t insert_far_field(GaussianMap& map, const FarFieldView& view,
                             const RenderResult<float>* render, const FarFieldSettings& s,
                             double cover, double opacity, double max_alpha, double max_sd_m);

}  // namespace vigs::mapping
