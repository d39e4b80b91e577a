#include "mapping/raster_simd.hpp"

namespace vigs::mapping {

#if defined(VIGS_MAPPING_AVX2) && (defined(__x86_64__) || defined(__i386__))
bool avx2_kernel_available() {
  static const bool ok = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return ok;
}
#else
bool avx2_kernel_available() {
  return false;
}
void forward_tile_avx2(const TileRect& rect, const TileGaussian<float>* gs, int count,
                       const RasterSettings& s, PixelOutputs<float>& out) {
  forward_tile_scalar(rect, gs, count, s, out);
}
#endif

}  // namespace vigs::mapping
