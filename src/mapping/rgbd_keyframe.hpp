#pragma once
// Keyframe points from a registered RGB-D image for tools that run the mapping back end alone
// (`vigs map`, benchmarks): every `stride`-th pixel with valid depth is back-projected, and its
// covariance is the sample covariance of the 3x3 grid of back-projected neighbours `stride`
// pixels apart (an image-grid stand-in for the tracker's kNN covariances), skipping neighbours
// across depth discontinuities. The colour is the patch's mean (footprint_colours).
#include "core/types/image.hpp"
#include "core/types/pinhole_camera.hpp"
#include "core/types/rgbd_view.hpp"
#include "mapping/keyframe_gaussians.hpp"

namespace vigs::mapping {

struct RgbdSampling {
  int stride_px = 4;
  double min_depth_m = 0.1;
  double max_depth_m = 10.0;
  double max_relative_jump = 0.1;  ///< neighbours with |z - z0| > this * z0 are ignored
};

/// One frame (core/types/rgbd_view.hpp); the frame's size, not the camera's, bounds the
/// pixels visited.
KeyframeGaussians keyframe_from_rgbd(const PinholeCamera& cam, const RgbdView& frame,
                                     const Eigen::Isometry3d& T_w_c, const RgbdSampling& s = {});
/// Owned images: rgb 3 channels, same size as depth (metres, 0 = invalid); throws
/// std::invalid_argument otherwise.
KeyframeGaussians keyframe_from_rgbd(const PinholeCamera& cam, const ImageU8& rgb,
                                     const ImageF32& depth_m, const Eigen::Isometry3d& T_w_c,
                                     const RgbdSampling& s = {});

/// Recolours every point with the mean colour of the pixels within stride_px / 2 of the pixel
/// it projects to whose depth is within max_relative_jump of the point's (a sample stands for
/// its patch, so a point colour aliases the texture); points outside the image keep theirs.
void footprint_colours(const PinholeCamera& cam, const RgbdView& frame, int stride_px,
                       KeyframeGaussians& kf, double max_relative_jump = 0.1);

}  // namespace vigs::mapping
