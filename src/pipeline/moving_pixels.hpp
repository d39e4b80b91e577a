#pragma once
// People out of the keyframe's training view: the pixels of the points the tracker flagged
// moving (tracking::Keyframe::moving) get depth -1 in the keyframe's depth image, which the
// mapper reads as "a moving object stood here: neither colour nor depth is a target"
// (mapping/loss.hpp), not "no depth, far away" (mapping/far_field.hpp), and no see-through vote
// (mapping/see_through.hpp). Each point is projected back to its pixel (the cloud was sampled
// from this image every stride-th pixel) and the square of half-width stride / 2 + dilation
// around it is marked: the stride block the sample stands for, widened to cover the silhouette's
// edge between samples. In the pipeline, which joins tracking and mapping, so that neither
// knows the other.
#include <cstddef>

#include "core/types/image.hpp"
#include "core/types/pinhole_camera.hpp"
#include "tracking/gaussian_cloud.hpp"

namespace vigs::pipeline {

/// Marks the pixels of kf's moving points with -1 in `depth_m` (kf's own frame, metres, the
/// camera's size). `stride_px` is the tracker's pixel stride. Returns the pixels marked. Does
/// nothing when kf has no flags or depth_m is not of the camera's size.
std::size_t mask_moving_pixels(const tracking::Keyframe& kf, const PinholeCamera& camera,
                               int stride_px, int dilation_px, ImageF32& depth_m);

}  // namespace vigs::pipeline
