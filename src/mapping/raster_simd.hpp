#pragma once
// Run-time dispatch to the AVX2 forward kernel. The kernel lives in its own translation unit
// compiled with -mavx2 -mfma (x86-64 only); everywhere else avx2_kernel_available() is false and
// the portable scalar kernel runs.
#include "mapping/tile_kernels.hpp"

namespace vigs::mapping {

/// True when the AVX2 kernel was compiled in and this CPU supports AVX2 and FMA.
bool avx2_kernel_available();

/// Same contract as forward_tile_scalar<float>; only call when avx2_kernel_available().
void forward_tile_avx2(const TileRect& rect, const TileGaussian<float>* gs, int count,
                       const RasterSettings& s, PixelOutputs<float>& out);

}  // namespace vigs::mapping
