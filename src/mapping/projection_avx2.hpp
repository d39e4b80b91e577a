#pragma once
// The covariance part of project_gaussian() for eight Gaussians at a time (AVX2), for those that
// passed may_reach_image(). A half-resolution iteration pays the projection in full for every
// Gaussian of the visible blocks, where its pixel work is a quarter: per Gaussian it had become
// the largest stage after the blending (9 % of a live run's samples). The arithmetic is
// project_gaussian()'s, operation for operation, in its own translation unit compiled with
// -ffp-contract=off: every product and sum rounds as the scalar code's do, so the result is the
// same bit for bit (tests/mapping/test_projection_avx2.cpp). The exponentials of the log-scales
// are taken by the caller (std::exp, as the scalar code), outside the -mavx2 unit.
#include <cstddef>
#include <cstdint>

#include "mapping/render_camera.hpp"

namespace vigs::mapping {

/// Gaussians in structure-of-arrays lanes: the inputs the caller fills and the outputs.
struct ProjectionLanes {
  static constexpr int kLanes = 64;  ///< a multiple of 8
  alignas(32) float mean_w[3][kLanes];
  alignas(32) float scale[3][kLanes];  ///< exp(log_scale)
  alignas(32) float quat_wxyz[4][kLanes];
  alignas(32) float mean2d[2][kLanes];
  alignas(32) float conic[3][kLanes];
  alignas(32) float depth[kLanes];
  alignas(32) int radius[kLanes];  ///< 0 = culled (degenerate or off-screen)
};

/// The camera as project_gaussian() converts it to float.
struct ProjectionCamera {
  float R_c_w[9], t_c_w[3];
  float fx, fy, cx, cy;
  float lim_x, lim_y;  ///< 1.3 x the half field of view's tangent
  float max_x, max_y;  ///< width - 1, height - 1
  float eps2d;

  static ProjectionCamera from(const RenderCamera& cam, float eps2d_px2);
};

/// A conservative first pass over [b, e) (eight at a time, AVX2): writes to `candidates` the
/// ids that may pass the opacity test (sigmoid(logit) >= min_alpha, given as its logit
/// `logit_min`) and may_reach_image(), and returns how many. A Gaussian it leaves out fails one
/// of them for certain: its tests keep a margin (1 mm in depth, 1 % in the opacity logit,
/// 0.1 % + 1.5 px in the radius bound) far beyond the rounding of its own arithmetic and
/// exponential, so the caller's exact tests on the candidates decide as the scalar loop does.
/// The tail of fewer than eight is passed on whole. `candidates` holds e - b ids.
int cull_candidates_avx2(const ProjectionCamera& cam, float near_m, float logit_min,
                         const float* mean_w, const float* log_scale, const float* opacity_logit,
                         std::size_t b, std::size_t e, std::uint32_t* candidates);

/// Projects lanes [0, n) (n a multiple of 8, at most kLanes) as project_gaussian() does after
/// may_reach_image(). Only call when avx2_kernel_available() (raster_simd.hpp).
void project_lanes_avx2(const ProjectionCamera& cam, ProjectionLanes& lanes, int n);

}  // namespace vigs::mapping
