#include "mapping/simd_axpy.hpp"

#include "mapping/raster_simd.hpp"

namespace vigs::mapping {

#if !(defined(VIGS_MAPPING_AVX2) && (defined(__x86_64__) || defined(__i386__)))
void axpy_avx2(float* o, const float* s, float w, int n) {
  axpy_plain(o, s, w, n);
}
#endif

void axpy(float* o, const float* s, float w, int n) {
  if (avx2_kernel_available()) {
    axpy_avx2(o, s, w, n);
  } else {
    axpy_plain(o, s, w, n);
  }
}

}  // namespace vigs::mapping
