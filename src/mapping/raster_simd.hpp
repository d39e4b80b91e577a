#pragma once
// Run-time dispatch to the AVX-512 and AVX2 forward and backward kernels. They live in their own
// translation units compiled with -mavx512f / -mavx2 -mfma (x86-64 only); everywhere else
// avx2_kernel_available() and avx512_kernel_available() are false and the portable scalar kernel
// runs.
#include <algorithm>
#include <cstddef>

#include "mapping/tile_kernels.hpp"

namespace vigs::mapping {

/// True when the AVX2 kernel was compiled in and this CPU supports AVX2 and FMA.
bool avx2_kernel_available();
/// True when the AVX-512 kernels were compiled in and this CPU supports AVX-512 F and DQ (and
/// the AVX2 kernel's checks).
bool avx512_kernel_available();

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

/// Blocks of 8 columns by 2 rows of a tile (the AVX-512 kernels' vectors): ceil(width / 8) per
/// row pair, numbered row pair by row pair.
inline int tile_blocks(const TileRect& r) {
  return (r.y1 - r.y0 + 1) / 2 * ((r.x1 - r.x0 + 7) / 8);
}

/// Block b of a tile: its first pixel and its size (8 x 2 but at the tile's right and bottom
/// edges).
struct PixelBlock {
  int x0, y0, w, h;
};
inline PixelBlock tile_block(const TileRect& r, int b) {
  const int cols = (r.x1 - r.x0 + 7) / 8;
  const int x0 = r.x0 + 8 * (b % cols), y0 = r.y0 + 2 * (b / cols);
  return {x0, y0, std::min(8, r.x1 - x0), std::min(2, r.y1 - y0)};
}

/// Ints of scratch the AVX-512 kernels need for a tile of `count` Gaussians: per block, the
/// indices of the Gaussians that can reach it (depth order) and their number, 16 ints of padding
/// (lists are stored 16 at a time), and each Gaussian's row and column masks.
inline std::size_t tile_block_scratch(const TileRect& r, int count) {
  const auto n = static_cast<std::size_t>(count);
  return static_cast<std::size_t>(tile_blocks(r)) * (n + 1) + 16 + 2 * ((n + 15) / 16 * 16);
}

/// Floats of gradient scratch the AVX-512 backward kernel needs for `count` Gaussians: 160 per
/// Gaussian and 16 for its 64-byte alignment.
inline std::size_t tile_grad_scratch_avx512(int count) {
  return static_cast<std::size_t>(count) * 160 + 16;
}

/// Same contract as forward_tile_avx2, one 16-lane vector per 8 x 2 pixel block;
/// `blocks` holds tile_block_scratch(rect, count) ints. Only call when avx512_kernel_available().
void forward_tile_avx512(const TileRect& rect, const TileGaussian<float>* gs, int count,
                         const RasterSettings& s, PixelOutputs<float>& out, int* blocks);

/// Same contract as backward_tile_avx2; `scratch` holds tile_grad_scratch_avx512(count) floats,
/// `blocks` tile_block_scratch(rect, count) ints. Only call when avx512_kernel_available().
void backward_tile_avx512(const TileRect& rect, const TileGaussian<float>* gs, int count,
                          const RasterSettings& s, int width, const float* final_T_img,
                          const int* n_contrib_img, const float* v_color, const float* v_depth,
                          const float* v_alpha, TileGrad<float>* grads, float* scratch,
                          int* blocks);

/// Fills `blocks` (tile_block_scratch(rect, count) ints): the first tile_blocks(rect) ints are
/// each block's count, then block b's indices start at tile_blocks(rect) + b * count. A Gaussian
/// is listed when out_of_reach() is false for one of the block's rows over its columns. AVX-512
/// kernels only.
void fill_tile_blocks_avx512(const TileRect& rect, const TileGaussian<float>* gs, int count,
                             int* blocks);

}  // namespace vigs::mapping
