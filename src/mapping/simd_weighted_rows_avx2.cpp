// AVX2 + FMA weighted row sums for SSIM's filters; compiled with -mavx2 -mfma, called only after
// the run-time check in simd_weighted_rows.cpp.
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include "mapping/simd_weighted_rows.hpp"

namespace vigs::mapping {

void weighted_rows_avx2(float* o, const float* const* rows, const float* w, int n_rows, int n) {
  int i = 0;
  // 32 outputs at a time: four independent accumulators hide the multiply-add's latency (one
  // chain of 11 taps would wait on itself).
  for (; i + 32 <= n; i += 32) {
    __m256 a0 = _mm256_setzero_ps(), a1 = a0, a2 = a0, a3 = a0;
    for (int k = 0; k < n_rows; ++k) {
      const __m256 wk = _mm256_set1_ps(w[k]);
      const float* s = rows[k] + i;
      a0 = _mm256_fmadd_ps(wk, _mm256_loadu_ps(s), a0);
      a1 = _mm256_fmadd_ps(wk, _mm256_loadu_ps(s + 8), a1);
      a2 = _mm256_fmadd_ps(wk, _mm256_loadu_ps(s + 16), a2);
      a3 = _mm256_fmadd_ps(wk, _mm256_loadu_ps(s + 24), a3);
    }
    _mm256_storeu_ps(o + i, a0);
    _mm256_storeu_ps(o + i + 8, a1);
    _mm256_storeu_ps(o + i + 16, a2);
    _mm256_storeu_ps(o + i + 24, a3);
  }
  for (; i + 8 <= n; i += 8) {
    __m256 a = _mm256_setzero_ps();
    for (int k = 0; k < n_rows; ++k)
      a = _mm256_fmadd_ps(_mm256_set1_ps(w[k]), _mm256_loadu_ps(rows[k] + i), a);
    _mm256_storeu_ps(o + i, a);
  }
  for (; i < n; ++i) {
    float a = 0;
    for (int k = 0; k < n_rows; ++k) a += w[k] * rows[k][i];
    o[i] = a;
  }
}

}  // namespace vigs::mapping
#endif
