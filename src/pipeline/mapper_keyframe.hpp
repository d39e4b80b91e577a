#pragma once
// The mapper's keyframe (mapping::MapperKeyframe) from a tracking keyframe and its images: one
// builder for the live mapper (`vigs run`) and the lockstep replay (`vigs replay`), so that
// both insert alike. The live mapper once built its own and skipped the patch colours: every
// real-time Gaussian took the colour of the one pixel its sample fell on (the texture aliased
// in the map and in the insertion gate's colour test), where the replay's took the patch mean.
//
// In order: the pixels of points the tracker flagged moving get depth -1
// (moving_pixels.hpp, when enabled), so that they give no colour below; those points are left
// out and the rest become footprint-sized Gaussians at the tracker's pixel stride
// (tracking_keyframe.hpp); each takes the mean colour of its patch (mapping::footprint_colours);
// the images become the training view (colour in [0, 1]). Allocates: mapper side only.
#include <cstdint>
#include <memory>

#include "core/config/mapping_components.hpp"
#include "core/geometry/se3.hpp"
#include "core/types/image.hpp"
#include "core/types/pinhole_camera.hpp"
#include "mapping/mapper.hpp"
#include "tracking/gaussian_cloud.hpp"

namespace vigs::pipeline {

/// `rgb`: 3 channels, the size of `depth_m` (metres, 0 = no measurement). `stride_px`: the
/// tracker's pixel stride (the points' footprint). `T_w_c_map`: where the map places the
/// keyframe (its loop-corrected pose, map_loop_correction.hpp); null: the tracker's kf.T_w_c.
std::unique_ptr<mapping::MapperKeyframe> make_mapper_keyframe(
    std::uint64_t id, const tracking::Keyframe& kf, const PinholeCamera& camera, int stride_px,
    const config::MovingMaskSettings& moving_mask, const ImageU8& rgb, ImageF32 depth_m,
    const geometry::Pose* T_w_c_map = nullptr);

}  // namespace vigs::pipeline
