// AVX2 forward blending kernel: 8 pixels of a tile row per vector, one Gaussian broadcast at a
// time, with per-lane termination masks. Compiled with -mavx2 -mfma and only called after the
// run-time check in raster_simd.cpp. The arithmetic follows the scalar kernel's order (no fused
// multiply-add in the decisions) and exp is a Cephes-style polynomial (about 1 ulp), so images
// agree with the scalar path to well within 1e-5.
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include <algorithm>

#include "mapping/avx2_math.hpp"
#include "mapping/raster_simd.hpp"

namespace vigs::mapping {

void fill_tile_runs_avx2(const TileRect& rect, const TileGaussian<float>* gs, int count,
                         int* runs) {
  // Without branches (an index is written, then kept only if the Gaussian reaches the run), so
  // that neither kernel has an unpredictable skip branch per Gaussian and run.
  const int n_runs = tile_runs(rect);
  int* sizes = runs;
  int* lists = runs + n_runs;
  for (int r = 0; r < n_runs; ++r) sizes[r] = 0;
  for (int k = 0; k < count; ++k) {
    const TileGaussian<float>& g = gs[k];
    int run = 0;
    for (int py = rect.y0; py < rect.y1; ++py) {
      const float fy = static_cast<float>(py);
      for (int x0 = rect.x0; x0 < rect.x1; x0 += 8, ++run) {
        const int x1 = x0 + std::min(8, rect.x1 - x0) - 1;
        const bool reach = !out_of_reach(g, static_cast<float>(x0), static_cast<float>(x1), fy);
        lists[run * count + sizes[run]] = k;
        sizes[run] += reach ? 1 : 0;
      }
    }
  }
}

void forward_tile_avx2(const TileRect& rect, const TileGaussian<float>* gs, int count,
                       const RasterSettings& s, PixelOutputs<float>& out, int* runs) {
  const __m256 min_alpha = _mm256_set1_ps(static_cast<float>(s.min_alpha));
  const __m256 max_alpha = _mm256_set1_ps(static_cast<float>(s.max_alpha));
  const __m256 min_T = _mm256_set1_ps(static_cast<float>(s.min_transmittance));
  const __m256 half = _mm256_set1_ps(0.5f), one = _mm256_set1_ps(1.0f), zero = _mm256_setzero_ps();
  const __m256 lane = _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7);
  fill_tile_runs_avx2(rect, gs, count, runs);
  const int n_runs = tile_runs(rect);
  int run = 0;
  for (int py = rect.y0; py < rect.y1; ++py) {
    const float fy = static_cast<float>(py);
    for (int x0 = rect.x0; x0 < rect.x1; x0 += 8, ++run) {
      const int* list = runs + n_runs + run * count;
      const int n_list = runs[run];
      const int lanes = std::min(8, rect.x1 - x0);
      const __m256 px = _mm256_add_ps(_mm256_set1_ps(static_cast<float>(x0)), lane);
      __m256 Tr = one, c0 = zero, c1 = zero, c2 = zero, d = zero, last = zero;
      // lanes beyond the tile edge start finished
      __m256 done = _mm256_cmp_ps(lane, _mm256_set1_ps(static_cast<float>(lanes)), _CMP_GE_OQ);
      for (int j = 0; j < n_list; ++j) {
        const int k = list[j];
        const TileGaussian<float>& g = gs[k];
        const __m256 dx = _mm256_sub_ps(_mm256_set1_ps(g.x), px);
        const float dy = g.y - fy;
        // sigma = 0.5 * (ca dx^2 + cc dy^2) + cb dx dy, in the scalar kernel's order
        const __m256 ca_dx2 = _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(g.ca), dx), dx);
        const __m256 sum = _mm256_add_ps(ca_dx2, _mm256_set1_ps(g.cc * dy * dy));
        const __m256 cross =
            _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(g.cb), dx), _mm256_set1_ps(dy));
        const __m256 sigma = _mm256_add_ps(_mm256_mul_ps(half, sum), cross);
        __m256 valid = _mm256_and_ps(_mm256_cmp_ps(sigma, zero, _CMP_GE_OQ),
                                     _mm256_cmp_ps(sigma, _mm256_set1_ps(g.sigma_cut), _CMP_LE_OQ));
        valid = _mm256_andnot_ps(done, valid);
        if (_mm256_movemask_ps(valid) == 0) continue;
        const __m256 vis = avx2::exp_neg_ps(_mm256_sub_ps(zero, sigma));
        const __m256 alpha =
            _mm256_min_ps(max_alpha, _mm256_mul_ps(_mm256_set1_ps(g.opacity), vis));
        valid = _mm256_and_ps(valid, _mm256_cmp_ps(alpha, min_alpha, _CMP_GE_OQ));
        valid = _mm256_andnot_ps(done, valid);
        const __m256 next_T = _mm256_mul_ps(Tr, _mm256_sub_ps(one, alpha));
        const __m256 stop = _mm256_and_ps(valid, _mm256_cmp_ps(next_T, min_T, _CMP_LE_OQ));
        done = _mm256_or_ps(done, stop);
        const __m256 take = _mm256_andnot_ps(stop, valid);
        const __m256 w = _mm256_and_ps(take, _mm256_mul_ps(alpha, Tr));
        c0 = _mm256_add_ps(c0, _mm256_mul_ps(w, _mm256_set1_ps(g.r)));
        c1 = _mm256_add_ps(c1, _mm256_mul_ps(w, _mm256_set1_ps(g.g)));
        c2 = _mm256_add_ps(c2, _mm256_mul_ps(w, _mm256_set1_ps(g.b)));
        d = _mm256_add_ps(d, _mm256_mul_ps(w, _mm256_set1_ps(g.z)));
        Tr = _mm256_blendv_ps(Tr, next_T, take);
        last = _mm256_blendv_ps(last, _mm256_set1_ps(static_cast<float>(k + 1)), take);
        if (_mm256_movemask_ps(done) == 0xFF) break;
      }
      alignas(32) float bc0[8], bc1[8], bc2[8], bd[8], bT[8], bl[8];
      _mm256_store_ps(bc0, c0);
      _mm256_store_ps(bc1, c1);
      _mm256_store_ps(bc2, c2);
      _mm256_store_ps(bd, d);
      _mm256_store_ps(bT, Tr);
      _mm256_store_ps(bl, last);
      for (int l = 0; l < lanes; ++l) {
        const int p = py * out.width + x0 + l;
        out.color[3 * p] = bc0[l];
        out.color[3 * p + 1] = bc1[l];
        out.color[3 * p + 2] = bc2[l];
        out.depth[p] = bd[l];
        out.final_T[p] = bT[l];
        out.n_contrib[p] = static_cast<int>(bl[l]);
      }
    }
  }
}

}  // namespace vigs::mapping
#endif
