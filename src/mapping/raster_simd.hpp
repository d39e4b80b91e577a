#pragma once
// Run-time dispatch to the AVX2 forward and backward kernels. They live in its own translation unit
// compiled with -mavx2 -mfma (x86-64 only); everywhere else avx2_kernel_available() is false and
// the portable scalar kernel runs.
#include "mapping/tile_kernels.hpp"

namespace vigs::mapping {

/// True when the AVX2 kernel was compiled in and this CPU supports AVX2 and FMA.
bool avx2_kernel_available();

/// Same contract as forward_tile_scalar<float>; only call when avx2_kernel_available().
void forward_tile_avx2(const TileRect& rect, const TileGaussian<float>* gs, int count,
                       const RasterSettings& s, PixelOutputs<float>& out);

/// Same contract as backward_tile_scalar<float>; `scratch` holds 80 floats per tile Gaussian.
/// Only call when avx2_kernel_available().
void backward_tile_avx2(const TileRect& rect, const TileGaussian<float>* gs, int count,
                        const RasterSettings& s, int width, const float* final_T_img,
                        const int* n_contrib_img, const float* v_color, const float* v_depth,
                        const float* v_alpha, TileGrad<float>* grads, float* scratch);

}  // namespace vigs::mapping
