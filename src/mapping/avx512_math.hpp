#pragma once
// AVX-512 helpers shared by the AVX-512 kernels. Include only from translation units compiled
// with -mavx512f (x86-64). Same polynomial as avx2_math.hpp, sixteen lanes.
#include <immintrin.h>

namespace vigs::mapping::avx512 {

/// exp(x) for x <= 0 (inputs below -87 give 0).
inline __m512 exp_neg_ps(__m512 x) {
  const __m512 lo = _mm512_set1_ps(-87.3f);
  const __mmask16 kept = _mm512_cmp_ps_mask(x, lo, _CMP_GE_OQ);
  x = _mm512_max_ps(x, lo);
  const __m512 log2e = _mm512_set1_ps(1.44269504088896341f);
  const __m512 n =
      _mm512_roundscale_ps(_mm512_mul_ps(x, log2e), _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
  // r = x - n ln2 in two parts (Cody-Waite)
  __m512 r = _mm512_sub_ps(x, _mm512_mul_ps(n, _mm512_set1_ps(0.693359375f)));
  r = _mm512_sub_ps(r, _mm512_mul_ps(n, _mm512_set1_ps(-2.12194440e-4f)));
  const __m512 r2 = _mm512_mul_ps(r, r);
  __m512 p = _mm512_set1_ps(1.9875691500e-4f);
  p = _mm512_fmadd_ps(p, r, _mm512_set1_ps(1.3981999507e-3f));
  p = _mm512_fmadd_ps(p, r, _mm512_set1_ps(8.3334519073e-3f));
  p = _mm512_fmadd_ps(p, r, _mm512_set1_ps(4.1665795894e-2f));
  p = _mm512_fmadd_ps(p, r, _mm512_set1_ps(1.6666665459e-1f));
  p = _mm512_fmadd_ps(p, r, _mm512_set1_ps(5.0000001201e-1f));
  p = _mm512_fmadd_ps(p, r2, _mm512_add_ps(r, _mm512_set1_ps(1.0f)));
  const __m512i e =
      _mm512_slli_epi32(_mm512_add_epi32(_mm512_cvtps_epi32(n), _mm512_set1_epi32(127)), 23);
  return _mm512_maskz_mul_ps(kept, p, _mm512_castsi512_ps(e));
}

/// The pixel offsets of a block vector's lanes: lane l is column l % 8, row l / 8 of its 8 x 2
/// block (raster_avx512.cpp).
inline __m512 block_lane_x() {
  return _mm512_setr_ps(0, 1, 2, 3, 4, 5, 6, 7, 0, 1, 2, 3, 4, 5, 6, 7);
}
inline __m512 block_lane_y() {
  return _mm512_setr_ps(0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 1, 1);
}

/// The Gaussian's exponent at offsets (dx, dy): 0.5 (ca dx^2 + cc dy^2) + cb dx dy, in the
/// scalar kernel's order.
inline __m512 conic_sigma(float ca, float cb, float cc, __m512 dx, __m512 dy) {
  const __m512 ca_dx2 = _mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(ca), dx), dx);
  const __m512 cc_dy2 = _mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(cc), dy), dy);
  const __m512 cross = _mm512_mul_ps(_mm512_mul_ps(_mm512_set1_ps(cb), dx), dy);
  return _mm512_add_ps(_mm512_mul_ps(_mm512_set1_ps(0.5f), _mm512_add_ps(ca_dx2, cc_dy2)), cross);
}

}  // namespace vigs::mapping::avx512
