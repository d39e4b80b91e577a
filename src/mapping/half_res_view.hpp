#pragma once
// A training view at half resolution (one pyramid level down), for the mapper's early
// iterations of a keyframe (mapping.coarse_iterations): a quarter of the pixels, so the render,
// its backward pass and SSIM cost about a quarter, while the Gaussians still see every part of
// the view. Each half-resolution pixel covers a 2x2 block of the full view:
// - colour: the block's mean (what the pixel's area shows);
// - depth: the mean of the block's valid depths on its nearest surface (within
//   kHalfResDepthTolerance of the nearest, relative), so a block across a depth edge takes the
//   front surface instead of a depth between the two that no surface has; 0 when no depth in the
//   block is valid; -1 (moving, masked) when any pixel of the block is masked moving;
// - camera: half the focal lengths, and the principal point moved so that pixel centres stay at
//   integer coordinates: the half-resolution pixel j covers full pixels 2j and 2j + 1, whose
//   centre is 2j + 0.5, so cx_half = (cx - 0.5) / 2; pixels twice the size (pixel_size), so the
//   rasterizer's low-pass filter is a quarter as many of them and blurs as much of the scene.
// An odd last row or column is dropped (a full-resolution view of W x H gives W/2 x H/2).
#include <vector>

#include "mapping/render_camera.hpp"

namespace vigs::mapping {

inline constexpr float kHalfResDepthTolerance = 0.05f;  ///< of the block's nearest depth

struct HalfResView {
  RenderCamera camera;
  std::vector<float> rgb;      ///< 3 per pixel, [0, 1]
  std::vector<float> depth_m;  ///< 1 per pixel, 0 = missing, < 0 = moving (masked); empty if
                               ///< the full view has no depth
};

/// The camera one pyramid level down (same pose).
RenderCamera half_res_camera(const RenderCamera& full);

/// Fills `out` from a full-resolution view (`depth_m` may be null). Reuses out's storage.
void make_half_res_view(const RenderCamera& camera, const float* rgb, const float* depth_m,
                        HalfResView& out);

}  // namespace vigs::mapping
