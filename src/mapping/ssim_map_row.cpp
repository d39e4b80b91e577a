#include "mapping/ssim_map_row.hpp"

#include "mapping/raster_simd.hpp"

namespace vigs::mapping {

#if !(defined(VIGS_MAPPING_AVX2) && (defined(__x86_64__) || defined(__i386__)))
double ssim_map_row_avx2(const float* const* m, const float* on_mask, const SsimRowTerms<float>& t,
                         float* const* g, int n) {
  return ssim_map_row_plain(m, on_mask, t, g, n);
}
#endif

double ssim_map_row(const float* const* m, const float* on_mask, const SsimRowTerms<float>& t,
                    float* const* g, int n) {
  if (avx2_kernel_available()) return ssim_map_row_avx2(m, on_mask, t, g, n);
  return ssim_map_row_plain(m, on_mask, t, g, n);
}

}  // namespace vigs::mapping
