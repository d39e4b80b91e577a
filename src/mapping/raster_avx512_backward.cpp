// AVX-512 backward blending kernel: sixteen pixels per vector, a block of 8 columns by 2 rows of
// a tile (raster_avx512.cpp says why), each pixel traversing its contributors in reverse from
// its own last one (lane masks). The same math as the AVX2 kernel (raster_avx2_backward.cpp),
// twice the lanes: per tile Gaussian the 10 gradient sums are 16-lane vectors in `scratch`,
// reduced once per tile. Gradients agree with the scalar kernel to rounding. Compiled with
// -mavx512f -mavx512dq -mfma; called only after the run-time check in raster_simd.cpp.
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include <algorithm>
#include <cstdint>

#include "mapping/avx512_math.hpp"
#include "mapping/raster_simd.hpp"

namespace vigs::mapping {

namespace {

inline void acc_add(float* p, __m512 v) {
  _mm512_store_ps(p, _mm512_add_ps(_mm512_load_ps(p), v));
}

constexpr int kFields = 10;  // TileGrad: x y ca cb cc opacity r g b z

}  // namespace

void backward_tile_avx512(const TileRect& rect, const TileGaussian<float>* gs, int count,
                          const RasterSettings& s, int width, const float* final_T_img,
                          const int* n_contrib_img, const float* v_color, const float* v_depth,
                          const float* v_alpha, TileGrad<float>* grads, float* scratch,
                          int* blocks) {
  // 64-byte aligned sums (the caller's buffer holds 16 floats more than the sums)
  const auto misalign = reinterpret_cast<std::uintptr_t>(scratch) % 64;
  float* acc0 = misalign == 0 ? scratch : scratch + (64 - misalign) / sizeof(float);
  std::fill(acc0, acc0 + static_cast<std::size_t>(count) * kFields * 16, 0.0f);
  const __m512 min_alpha = _mm512_set1_ps(static_cast<float>(s.min_alpha));
  const __m512 max_alpha = _mm512_set1_ps(static_cast<float>(s.max_alpha));
  const __m512 half = _mm512_set1_ps(0.5f), one = _mm512_set1_ps(1.0f), zero = _mm512_setzero_ps();
  const __m512 lane_x = avx512::block_lane_x(), lane_y = avx512::block_lane_y();
  fill_tile_blocks_avx512(rect, gs, count, blocks);
  const int n_blocks = tile_blocks(rect);
  for (int block = 0; block < n_blocks; ++block) {
    const PixelBlock pb = tile_block(rect, block);
    // lanes beyond the edge: T 1, no gradient, and no contributor (last 0)
    alignas(64) float last_f[16] = {}, c0[16] = {}, c1[16] = {}, c2[16] = {}, vd[16] = {},
                      va[16] = {}, tf[16];
    int k_max = 0;
    for (int i = 0; i < 16; ++i) tf[i] = 1.0f;
    for (int r = 0; r < pb.h; ++r)
      for (int l = 0; l < pb.w; ++l) {
        const int p = (pb.y0 + r) * width + pb.x0 + l, i = 8 * r + l;
        const int last = n_contrib_img[p];
        k_max = std::max(k_max, last);
        last_f[i] = static_cast<float>(last);
        tf[i] = final_T_img[p];
        c0[i] = v_color[3 * p];
        c1[i] = v_color[3 * p + 1];
        c2[i] = v_color[3 * p + 2];
        if (v_depth) vd[i] = v_depth[p];
        if (v_alpha) va[i] = v_alpha[p];
      }
    if (k_max == 0) continue;
    const __m512 lastv = _mm512_load_ps(last_f), Tf = _mm512_load_ps(tf);
    const __m512 vc0 = _mm512_load_ps(c0), vc1 = _mm512_load_ps(c1), vc2 = _mm512_load_ps(c2);
    const __m512 vdd = _mm512_load_ps(vd), vaa = _mm512_load_ps(va);
    const __m512 px = _mm512_add_ps(_mm512_set1_ps(static_cast<float>(pb.x0)), lane_x);
    const __m512 py = _mm512_add_ps(_mm512_set1_ps(static_cast<float>(pb.y0)), lane_y);
    __m512 Tr = Tf, b0 = zero, b1 = zero, b2 = zero, bd = zero;
    // the block's reaching Gaussians below k_max, in reverse
    const int* list = blocks + n_blocks + block * count;
    int j = blocks[block] - 1;
    while (j >= 0 && list[j] >= k_max) --j;
    for (; j >= 0; --j) {
      const int k = list[j];
      const TileGaussian<float>& g = gs[k];
      const __mmask16 active =
          _mm512_cmp_ps_mask(_mm512_set1_ps(static_cast<float>(k)), lastv, _CMP_LT_OQ);
      const __m512 dx = _mm512_sub_ps(_mm512_set1_ps(g.x), px);
      const __m512 dy = _mm512_sub_ps(_mm512_set1_ps(g.y), py);
      const __m512 sigma = avx512::conic_sigma(g.ca, g.cb, g.cc, dx, dy);
      __mmask16 valid = _mm512_mask_cmp_ps_mask(active, sigma, zero, _CMP_GE_OQ);
      valid = _mm512_mask_cmp_ps_mask(valid, sigma, _mm512_set1_ps(g.sigma_cut), _CMP_LE_OQ);
      if (valid == 0) continue;
      const __m512 vis = avx512::exp_neg_ps(_mm512_sub_ps(zero, sigma));
      const __m512 raw = _mm512_mul_ps(_mm512_set1_ps(g.opacity), vis);
      const __m512 alpha = _mm512_min_ps(max_alpha, raw);
      valid = _mm512_mask_cmp_ps_mask(valid, alpha, min_alpha, _CMP_GE_OQ);
      if (valid == 0) continue;
      const __m512 ra = _mm512_div_ps(one, _mm512_sub_ps(one, alpha));
      Tr = _mm512_mask_mul_ps(Tr, valid, Tr, ra);
      const __m512 w = _mm512_maskz_mul_ps(valid, alpha, Tr);
      float* acc = acc0 + static_cast<std::size_t>(k) * kFields * 16;
      const __m512 gr = _mm512_set1_ps(g.r), gg = _mm512_set1_ps(g.g), gb = _mm512_set1_ps(g.b);
      const __m512 gz = _mm512_set1_ps(g.z);
      acc_add(acc + 6 * 16, _mm512_mul_ps(w, vc0));
      acc_add(acc + 7 * 16, _mm512_mul_ps(w, vc1));
      acc_add(acc + 8 * 16, _mm512_mul_ps(w, vc2));
      acc_add(acc + 9 * 16, _mm512_mul_ps(w, vdd));
      __m512 v_a = _mm512_mul_ps(_mm512_sub_ps(_mm512_mul_ps(gr, Tr), _mm512_mul_ps(b0, ra)), vc0);
      v_a = _mm512_add_ps(
          v_a, _mm512_mul_ps(_mm512_sub_ps(_mm512_mul_ps(gg, Tr), _mm512_mul_ps(b1, ra)), vc1));
      v_a = _mm512_add_ps(
          v_a, _mm512_mul_ps(_mm512_sub_ps(_mm512_mul_ps(gb, Tr), _mm512_mul_ps(b2, ra)), vc2));
      v_a = _mm512_add_ps(
          v_a, _mm512_mul_ps(_mm512_sub_ps(_mm512_mul_ps(gz, Tr), _mm512_mul_ps(bd, ra)), vdd));
      v_a = _mm512_add_ps(v_a, _mm512_mul_ps(_mm512_mul_ps(Tf, ra), vaa));
      b0 = _mm512_add_ps(b0, _mm512_mul_ps(gr, w));
      b1 = _mm512_add_ps(b1, _mm512_mul_ps(gg, w));
      b2 = _mm512_add_ps(b2, _mm512_mul_ps(gb, w));
      bd = _mm512_add_ps(bd, _mm512_mul_ps(gz, w));
      const __mmask16 m2 = _mm512_mask_cmp_ps_mask(valid, raw, max_alpha, _CMP_LE_OQ);
      const __m512 v_sigma = _mm512_maskz_sub_ps(m2, zero, _mm512_mul_ps(raw, v_a));
      acc_add(acc + 2 * 16, _mm512_mul_ps(_mm512_mul_ps(half, _mm512_mul_ps(dx, dx)), v_sigma));
      acc_add(acc + 3 * 16, _mm512_mul_ps(_mm512_mul_ps(dx, dy), v_sigma));
      acc_add(acc + 4 * 16, _mm512_mul_ps(_mm512_mul_ps(half, _mm512_mul_ps(dy, dy)), v_sigma));
      const __m512 gx = _mm512_add_ps(_mm512_mul_ps(_mm512_set1_ps(g.ca), dx),
                                      _mm512_mul_ps(_mm512_set1_ps(g.cb), dy));
      const __m512 gy = _mm512_add_ps(_mm512_mul_ps(_mm512_set1_ps(g.cb), dx),
                                      _mm512_mul_ps(_mm512_set1_ps(g.cc), dy));
      acc_add(acc + 0 * 16, _mm512_mul_ps(v_sigma, gx));
      acc_add(acc + 1 * 16, _mm512_mul_ps(v_sigma, gy));
      acc_add(acc + 5 * 16, _mm512_maskz_mul_ps(m2, vis, v_a));
    }
  }
  for (int k = 0; k < count; ++k) {
    const float* acc = acc0 + static_cast<std::size_t>(k) * kFields * 16;
    TileGrad<float>& g = grads[k];
    g.x += _mm512_reduce_add_ps(_mm512_load_ps(acc));
    g.y += _mm512_reduce_add_ps(_mm512_load_ps(acc + 16));
    g.ca += _mm512_reduce_add_ps(_mm512_load_ps(acc + 32));
    g.cb += _mm512_reduce_add_ps(_mm512_load_ps(acc + 48));
    g.cc += _mm512_reduce_add_ps(_mm512_load_ps(acc + 64));
    g.opacity += _mm512_reduce_add_ps(_mm512_load_ps(acc + 80));
    g.r += _mm512_reduce_add_ps(_mm512_load_ps(acc + 96));
    g.g += _mm512_reduce_add_ps(_mm512_load_ps(acc + 112));
    g.b += _mm512_reduce_add_ps(_mm512_load_ps(acc + 128));
    g.z += _mm512_reduce_add_ps(_mm512_load_ps(acc + 144));
  }
}

}  // namespace vigs::mapping
#endif
