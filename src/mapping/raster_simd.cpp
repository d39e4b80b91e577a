#include "mapping/raster_simd.hpp"

namespace vigs::mapping {

#if defined(VIGS_MAPPING_AVX2) && (defined(__x86_64__) || defined(__i386__))
bool avx2_kernel_available() {
  static const bool ok = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return ok;
}
bool avx512_kernel_available() {
  static const bool ok = avx2_kernel_available() && __builtin_cpu_supports("avx512f") &&
                         __builtin_cpu_supports("avx512dq");
  return ok;
}
#else
bool avx2_kernel_available() {
  return false;
}
bool avx512_kernel_available() {
  return false;
}
void forward_tile_avx512(const TileRect& rect, const TileGaussian<float>* gs, int count,
                         const RasterSettings& s, PixelOutputs<float>& out, int*) {
  forward_tile_scalar(rect, gs, count, s, out);
}
void backward_tile_avx512(const TileRect& rect, const TileGaussian<float>* gs, int,
                          const RasterSettings& s, int width, const float* final_T_img,
                          const int* n_contrib_img, const float* v_color, const float* v_depth,
                          const float* v_alpha, TileGrad<float>* grads, float*, int*) {
  backward_tile_scalar(rect, gs, s, width, final_T_img, n_contrib_img, v_color, v_depth, v_alpha,
                       grads);
}
void forward_tile_avx2(const TileRect& rect, const TileGaussian<float>* gs, int count,
                       const RasterSettings& s, PixelOutputs<float>& out, int*) {
  forward_tile_scalar(rect, gs, count, s, out);
}
void backward_tile_avx2(const TileRect& rect, const TileGaussian<float>* gs, int,
                        const RasterSettings& s, int width, const float* final_T_img,
                        const int* n_contrib_img, const float* v_color, const float* v_depth,
                        const float* v_alpha, TileGrad<float>* grads, float*, int*) {
  backward_tile_scalar(rect, gs, s, width, final_T_img, n_contrib_img, v_color, v_depth, v_alpha,
                       grads);
}
#endif

}  // namespace vigs::mapping
