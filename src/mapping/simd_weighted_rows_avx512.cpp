// AVX-512 weighted row sums for SSIM's filters; compiled with -mavx512f, called only after the
// run-time check in simd_weighted_rows.cpp. Each output lane sums its taps in order k from zero
// with one fused multiply-add per tap, as weighted_rows_avx2() does (its scalar tail too: GCC
// contracts it), so the two give the same bits; the wider vectors halve the instructions per
// output on CPUs with full-width AVX-512.
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include "mapping/simd_weighted_rows.hpp"

namespace vigs::mapping {

void weighted_rows_avx512(float* o, const float* const* rows, const float* w, int n_rows, int n) {
  int i = 0;
  // 64 outputs at a time: four independent accumulators hide the multiply-add's latency.
  for (; i + 64 <= n; i += 64) {
    __m512 a0 = _mm512_setzero_ps(), a1 = a0, a2 = a0, a3 = a0;
    for (int k = 0; k < n_rows; ++k) {
      const __m512 wk = _mm512_set1_ps(w[k]);
      const float* s = rows[k] + i;
      a0 = _mm512_fmadd_ps(wk, _mm512_loadu_ps(s), a0);
      a1 = _mm512_fmadd_ps(wk, _mm512_loadu_ps(s + 16), a1);
      a2 = _mm512_fmadd_ps(wk, _mm512_loadu_ps(s + 32), a2);
      a3 = _mm512_fmadd_ps(wk, _mm512_loadu_ps(s + 48), a3);
    }
    _mm512_storeu_ps(o + i, a0);
    _mm512_storeu_ps(o + i + 16, a1);
    _mm512_storeu_ps(o + i + 32, a2);
    _mm512_storeu_ps(o + i + 48, a3);
  }
  // the rest 16 at a time, the last vector masked (nothing read or written past n)
  for (; i < n; i += 16) {
    const __mmask16 live = n - i >= 16
                               ? __mmask16(0xffff)
                               : static_cast<__mmask16>((1u << static_cast<unsigned>(n - i)) - 1u);
    __m512 a = _mm512_setzero_ps();
    for (int k = 0; k < n_rows; ++k)
      a = _mm512_fmadd_ps(_mm512_set1_ps(w[k]), _mm512_maskz_loadu_ps(live, rows[k] + i), a);
    _mm512_mask_storeu_ps(o + i, live, a);
  }
}

}  // namespace vigs::mapping
#endif
