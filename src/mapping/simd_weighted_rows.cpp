#include "mapping/simd_weighted_rows.hpp"

#include "mapping/raster_simd.hpp"

namespace vigs::mapping {

#if !(defined(VIGS_MAPPING_AVX2) && (defined(__x86_64__) || defined(__i386__)))
void weighted_rows_avx2(float* o, const float* const* rows, const float* w, int n_rows, int n) {
  weighted_rows_plain(o, rows, w, n_rows, n);
}
void weighted_rows_avx512(float* o, const float* const* rows, const float* w, int n_rows, int n) {
  weighted_rows_plain(o, rows, w, n_rows, n);
}
#endif

void weighted_rows(float* o, const float* const* rows, const float* w, int n_rows, int n,
                   bool avx512) {
  if (avx512 && avx512_kernel_available()) {
    weighted_rows_avx512(o, rows, w, n_rows, n);
  } else if (avx2_kernel_available()) {
    weighted_rows_avx2(o, rows, w, n_rows, n);
  } else {
    weighted_rows_plain(o, rows, w, n_rows, n);
  }
}

}  // namespace vigs::mapping
