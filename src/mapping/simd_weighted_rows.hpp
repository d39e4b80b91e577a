#pragma once
// o[i] = sum_k w[k] * rows[k][i]: one output row of SSIM's separable filters (ssim.cpp), where a
// 720x480 training iteration spent about a fifth of its time. Every tap of a row is summed in
// registers and o is written once, instead of one read-modify-write pass over o per tap. The
// AVX-512 and AVX2 + FMA versions live in their own translation units
// (simd_weighted_rows_avx512.cpp, simd_weighted_rows_avx2.cpp) and are chosen at run time, as the
// rasterizer's kernels are (raster_simd.hpp); everywhere else the plain loop runs.

namespace vigs::mapping {

/// o[i] = sum over k < n_rows of w[k] * rows[k][i], for 0 <= i < n, the taps summed in order k
/// (o must not overlap a row). Results can differ from the plain loop's in the last bit (fused
/// multiply-add), but are the same run to run on one CPU; the AVX-512 and AVX2 versions give the
/// same bits. `avx512`: use AVX-512 where the CPU has it (false: AVX2, the baseline).
void weighted_rows(float* o, const float* const* rows, const float* w, int n_rows, int n,
                   bool avx512 = true);

/// The plain loop, for doubles and for CPUs without AVX2.
template <class T>
inline void weighted_rows_plain(T* o, const T* const* rows, const T* w, int n_rows, int n) {
  for (int i = 0; i < n; ++i) o[i] = 0;
  for (int k = 0; k < n_rows; ++k) {
    const T* s = rows[k];
    const T wk = w[k];
    for (int i = 0; i < n; ++i) o[i] += wk * s[i];
  }
}

/// Only call when avx512_kernel_available() (raster_simd.hpp).
void weighted_rows_avx512(float* o, const float* const* rows, const float* w, int n_rows, int n);

/// Only call when avx2_kernel_available() (raster_simd.hpp).
void weighted_rows_avx2(float* o, const float* const* rows, const float* w, int n_rows, int n);

}  // namespace vigs::mapping
