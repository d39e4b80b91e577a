// AVX2 + FMA rows of SSIM's map; compiled with -mavx2 -mfma, called only after the run-time check
// in ssim_map_row.cpp. No standard library code here (see raster_simd.hpp).
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include "mapping/ssim_map_row.hpp"

namespace vigs::mapping {

double ssim_map_row_avx2(const float* const* m, const float* on_mask, const SsimRowTerms<float>& t,
                         float* const* g, int n) {
  const __m256 two = _mm256_set1_ps(2.0f), one = _mm256_set1_ps(1.0f), zero = _mm256_setzero_ps();
  const __m256 C1 = _mm256_set1_ps(t.C1), C2 = _mm256_set1_ps(t.C2), cn = _mm256_set1_ps(t.cn);
  const __m256 two_cn = _mm256_mul_ps(two, cn), inv_n = _mm256_set1_ps(t.inv_n);
  __m256d sum_lo = _mm256_setzero_pd(), sum_hi = _mm256_setzero_pd();
  // `valid`: the lanes inside the row (all but in the last, partial step; its other lanes load
  // zeros, give S = 1 and are neither summed nor stored).
  const auto step = [&](int i, bool partial, __m256i valid) {
    const auto load = [&](const float* p) {
      return partial ? _mm256_maskload_ps(p + i, valid) : _mm256_loadu_ps(p + i);
    };
    const auto store = [&](float* p, __m256 v) {
      if (partial) {
        _mm256_maskstore_ps(p + i, valid, v);
      } else {
        _mm256_storeu_ps(p + i, v);
      }
    };
    const __m256 ux = load(m[0]), uy = load(m[1]);
    const __m256 vx = _mm256_mul_ps(cn, _mm256_fnmadd_ps(ux, ux, load(m[2])));
    const __m256 vy = _mm256_mul_ps(cn, _mm256_fnmadd_ps(uy, uy, load(m[3])));
    const __m256 vxy = _mm256_mul_ps(cn, _mm256_fnmadd_ps(ux, uy, load(m[4])));
    const __m256 N1 = _mm256_fmadd_ps(_mm256_mul_ps(two, ux), uy, C1);
    const __m256 N2 = _mm256_fmadd_ps(two, vxy, C2);
    const __m256 D1 = _mm256_fmadd_ps(ux, ux, _mm256_fmadd_ps(uy, uy, C1));
    const __m256 D2 = _mm256_add_ps(_mm256_add_ps(vx, vy), C2);
    const __m256 S = _mm256_div_ps(_mm256_mul_ps(N1, N2), _mm256_mul_ps(D1, D2));
    __m256 on = _mm256_castsi256_ps(valid);
    if (on_mask) on = _mm256_and_ps(on, _mm256_cmp_ps(load(on_mask), zero, _CMP_GT_OQ));
    const __m256 S_on = _mm256_and_ps(S, on);
    sum_lo = _mm256_add_pd(sum_lo, _mm256_cvtps_pd(_mm256_castps256_ps128(S_on)));
    sum_hi = _mm256_add_pd(sum_hi, _mm256_cvtps_pd(_mm256_extractf128_ps(S_on, 1)));
    if (!g) return;
    const __m256 wS = _mm256_mul_ps(_mm256_and_ps(inv_n, on), S);
    const __m256 rN1 = _mm256_div_ps(one, N1), rN2 = _mm256_div_ps(one, N2);
    const __m256 rD1 = _mm256_div_ps(one, D1), rD2 = _mm256_div_ps(one, D2);
    // 2 uy / N1 - 2 cn uy / N2 - 2 ux / D1 + 2 cn ux / D2
    const __m256 a = _mm256_mul_ps(two, _mm256_fmsub_ps(uy, rN1, _mm256_mul_ps(ux, rD1)));
    const __m256 b = _mm256_mul_ps(two_cn, _mm256_fmsub_ps(ux, rD2, _mm256_mul_ps(uy, rN2)));
    store(g[0], _mm256_mul_ps(wS, _mm256_add_ps(a, b)));
    store(g[1], _mm256_mul_ps(wS, _mm256_sub_ps(zero, _mm256_mul_ps(cn, rD2))));
    store(g[2], _mm256_mul_ps(wS, _mm256_mul_ps(two_cn, rN2)));
  };
  const __m256i all = _mm256_set1_epi32(-1);
  int i = 0;
  for (; i + 8 <= n; i += 8) step(i, false, all);
  if (i < n) {
    const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    step(i, true, _mm256_cmpgt_epi32(_mm256_set1_epi32(n - i), lane));
  }
  double lanes[4];
  _mm256_storeu_pd(lanes, _mm256_add_pd(sum_lo, sum_hi));
  const double sum = (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
  return sum;
}

}  // namespace vigs::mapping
#endif
