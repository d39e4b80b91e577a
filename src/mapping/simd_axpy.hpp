#pragma once
// o[i] += w * s[i]: the inner loop of SSIM's separable filters (ssim.cpp), where a 720x480
// training iteration spends about a seventh of its time. The AVX2 + FMA version lives in its own
// translation unit (simd_axpy_avx2.cpp, -mavx2 -mfma) and is chosen at run time, as the
// rasterizer's kernels are (raster_simd.hpp); everywhere else the plain loop runs.

namespace vigs::mapping {

/// o[i] += w * s[i] for 0 <= i < n (o and s may not overlap). Results can differ from the
/// plain loop's in the last bit (fused multiply-add), but are the same run to run on one CPU.
void axpy(float* o, const float* s, float w, int n);

/// The plain loop, for doubles and for CPUs without AVX2.
template <class T>
inline void axpy_plain(T* o, const T* s, T w, int n) {
  for (int i = 0; i < n; ++i) o[i] += w * s[i];
}

/// Only call when avx2_kernel_available() (raster_simd.hpp).
void axpy_avx2(float* o, const float* s, float w, int n);

}  // namespace vigs::mapping
