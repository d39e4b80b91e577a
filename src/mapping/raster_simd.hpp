#pragma once
// Run-time dispatch to the AVX2 forward and backward kernels. They live in its own translation unit
// compiled with -mavx2 -mfma (x86-64 only); everywhere else avx2_kernel_available() is false and
// the portable scalar kernel runs.
#include <cstddef>

#include "mapping/tile_kernels.hpp"

namespace vigs::mapping {

/// True when the AVX2 kernel was compiled in and this CPU supports AVX2 and FMA.
bool avx2_kernel_available();

/// Runs of up to 8 pixels of a tile row: ceil(width / 8) per row, numbered row by row.
inline int tile_runs(const TileRect& r) {
  return (r.y1 - r.y0) * ((r.x1 - r.x0 + 7) / 8);
}

/// Ints of scratch the AVX2 kernels need for a tile of `count` Gaussians: per run, the indices
/// of the Gaussians that can reach it (out_of_reach false, depth order) and their number, 8
/// ints of padding (lists are stored 8 at a time), and each Gaussian's row and column masks.
/// The caller owns and sizes it (outside the -mavx2 translation units, so that no standard
/// library code is instantiated there).
inline std::size_t tile_run_scratch(const TileRect& r, int count) {
  const auto n = static_cast<std::size_t>(count);
  return static_cast<std::size_t>(tile_runs(r)) * (n + 1) + 8 + 2 * ((n + 7) / 8 * 8);
}

/// Same contract as forward_tile_scalar<float>; only call when avx2_kernel_available().
/// `runs`: tile_run_scratch(rect, count) ints.
void forward_tile_avx2(const TileRect& rect, const TileGaussian<float>* gs, int count,
                       const RasterSettings& s, PixelOutputs<float>& out, int* runs);

/// Same contract as backward_tile_scalar<float>; `scratch` holds 80 floats per tile Gaussian,
/// `runs` tile_run_scratch(rect, count) ints. Only call when avx2_kernel_available().
void backward_tile_avx2(const TileRect& rect, const TileGaussian<float>* gs, int count,
                        const RasterSettings& s, int width, const float* final_T_img,
                        const int* n_contrib_img, const float* v_color, const float* v_depth,
                        const float* v_alpha, TileGrad<float>* grads, float* scratch, int* runs);

/// Fills `runs` (tile_run_scratch(rect, count) ints): the first tile_runs(rect) ints are each
/// run's count, then run r's indices start at tile_runs(rect) + r * count. AVX2 kernels only.
void fill_tile_runs_avx2(const TileRect& rect, const TileGaussian<float>* gs, int count, int* runs);

}  // namespace vigs::mapping
