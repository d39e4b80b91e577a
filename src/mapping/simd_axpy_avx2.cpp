// AVX2 + FMA axpy for SSIM's filters; compiled with -mavx2 -mfma, called only after the run-time
// check in simd_axpy.cpp.
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include "mapping/simd_axpy.hpp"

namespace vigs::mapping {

void axpy_avx2(float* o, const float* s, float w, int n) {
  const __m256 wv = _mm256_set1_ps(w);
  int i = 0;
  for (; i + 8 <= n; i += 8)
    _mm256_storeu_ps(o + i, _mm256_fmadd_ps(wv, _mm256_loadu_ps(s + i), _mm256_loadu_ps(o + i)));
  for (; i < n; ++i) o[i] += w * s[i];
}

}  // namespace vigs::mapping
#endif
