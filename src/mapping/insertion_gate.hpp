#pragma once
// Insert only where the map is missing or wrong: before a keyframe's points become Gaussians,
// the map is rendered from the keyframe's own camera, and a point is kept only where that render
// does not already show it: accumulated opacity below `max_alpha` (nothing there), rendered
// depth (normalised by the opacity) off by more than `depth_rel` of the point's depth (another
// surface), or colour off by more than `color` (mean absolute RGB difference in [0, 1]). Memory
// then grows with the area seen, not with the time spent there.
#include <cstddef>
#include <vector>

#include "mapping/keyframe_gaussians.hpp"
#include "mapping/rasterizer.hpp"
#include "mapping/render_camera.hpp"

namespace vigs::mapping {

struct GateSettings {
  double max_alpha = 0.5;
  double depth_rel = 0.05;
  double color = 0.1;
};

/// keep[i] = 1 where point i of `kf` is missing or wrong in `render` (made from `cam`, the
/// keyframe's camera) or projects outside it, else 0. Returns the number kept.
std::size_t gate_points(const KeyframeGaussians& kf, const RenderCamera& cam,
                        const RenderResult<float>& render, const GateSettings& s,
                        std::vector<char>& keep);

}  // namespace vigs::mapping
