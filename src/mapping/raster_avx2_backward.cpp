// AVX2 backward blending kernel: 8 pixels of a tile row per vector, each pixel traversing its
// contributors in reverse from its own last one (lane masks). Per tile Gaussian the 10 gradient
// sums are kept as 8-lane vectors in `scratch` and reduced once per tile, so the inner loop has
// no horizontal adds. Same math as backward_tile_scalar; sums are taken in a different order, so
// gradients agree with the scalar kernel to rounding. Compiled with -mavx2 -mfma; called only
// after the run-time check in raster_simd.cpp.
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include <algorithm>

#include "mapping/avx2_math.hpp"
#include "mapping/raster_simd.hpp"

namespace vigs::mapping {

namespace {

inline float hsum(__m256 v) {
  const __m128 lo = _mm256_castps256_ps128(v), hi = _mm256_extractf128_ps(v, 1);
  __m128 s = _mm_add_ps(lo, hi);
  s = _mm_add_ps(s, _mm_movehl_ps(s, s));
  s = _mm_add_ss(s, _mm_shuffle_ps(s, s, 0x55));
  return _mm_cvtss_f32(s);
}

inline void acc_add(float* p, __m256 v) {
  _mm256_storeu_ps(p, _mm256_add_ps(_mm256_loadu_ps(p), v));
}

constexpr int kFields = 10;  // TileGrad: x y ca cb cc opacity r g b z

}  // namespace

void backward_tile_avx2(const TileRect& rect, const TileGaussian<float>* gs, int count,
                        const RasterSettings& s, int width, const float* final_T_img,
                        const int* n_contrib_img, const float* v_color, const float* v_depth,
                        const float* v_alpha, TileGrad<float>* grads, float* scratch, int* runs) {
  std::fill(scratch, scratch + static_cast<std::size_t>(count) * kFields * 8, 0.0f);
  const __m256 min_alpha = _mm256_set1_ps(static_cast<float>(s.min_alpha));
  const __m256 max_alpha = _mm256_set1_ps(static_cast<float>(s.max_alpha));
  const __m256 half = _mm256_set1_ps(0.5f), one = _mm256_set1_ps(1.0f), zero = _mm256_setzero_ps();
  const __m256 lane = _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7);
  fill_tile_runs_avx2(rect, gs, count, runs);
  const int n_runs = tile_runs(rect);
  int run = 0;
  for (int py = rect.y0; py < rect.y1; ++py) {
    const float fy = static_cast<float>(py);
    for (int x0 = rect.x0; x0 < rect.x1; x0 += 8, ++run) {
      const int lanes = std::min(8, rect.x1 - x0);
      alignas(32) float last_f[8] = {}, tf[8], c0[8] = {}, c1[8] = {}, c2[8] = {}, vd[8] = {},
                        va[8] = {};
      int k_max = 0;
      for (int l = 0; l < 8; ++l) {
        tf[l] = 1.0f;
        if (l >= lanes) continue;
        const int p = py * width + x0 + l;
        const int last = n_contrib_img[p];
        k_max = std::max(k_max, last);
        last_f[l] = static_cast<float>(last);
        tf[l] = final_T_img[p];
        c0[l] = v_color[3 * p];
        c1[l] = v_color[3 * p + 1];
        c2[l] = v_color[3 * p + 2];
        if (v_depth) vd[l] = v_depth[p];
        if (v_alpha) va[l] = v_alpha[p];
      }
      if (k_max == 0) continue;
      const __m256 lastv = _mm256_load_ps(last_f), Tf = _mm256_load_ps(tf);
      const __m256 vc0 = _mm256_load_ps(c0), vc1 = _mm256_load_ps(c1), vc2 = _mm256_load_ps(c2);
      const __m256 vdd = _mm256_load_ps(vd), vaa = _mm256_load_ps(va);
      const __m256 px = _mm256_add_ps(_mm256_set1_ps(static_cast<float>(x0)), lane);
      __m256 Tr = Tf, b0 = zero, b1 = zero, b2 = zero, bd = zero;
      // the run's reaching Gaussians below k_max, in reverse
      const int* list = runs + n_runs + run * count;
      int j = runs[run] - 1;
      while (j >= 0 && list[j] >= k_max) --j;
      for (; j >= 0; --j) {
        const int k = list[j];
        const TileGaussian<float>& g = gs[k];
        const __m256 active =
            _mm256_cmp_ps(_mm256_set1_ps(static_cast<float>(k)), lastv, _CMP_LT_OQ);
        const __m256 dx = _mm256_sub_ps(_mm256_set1_ps(g.x), px);
        const float dy = g.y - fy;
        const __m256 ca_dx2 = _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(g.ca), dx), dx);
        const __m256 sum = _mm256_add_ps(ca_dx2, _mm256_set1_ps(g.cc * dy * dy));
        const __m256 cross =
            _mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(g.cb), dx), _mm256_set1_ps(dy));
        const __m256 sigma = _mm256_add_ps(_mm256_mul_ps(half, sum), cross);
        __m256 valid = _mm256_and_ps(active, _mm256_cmp_ps(sigma, zero, _CMP_GE_OQ));
        valid = _mm256_and_ps(valid, _mm256_cmp_ps(sigma, _mm256_set1_ps(g.sigma_cut), _CMP_LE_OQ));
        if (_mm256_movemask_ps(valid) == 0) continue;
        const __m256 vis = avx2::exp_neg_ps(_mm256_sub_ps(zero, sigma));
        const __m256 raw = _mm256_mul_ps(_mm256_set1_ps(g.opacity), vis);
        const __m256 alpha = _mm256_min_ps(max_alpha, raw);
        valid = _mm256_and_ps(valid, _mm256_cmp_ps(alpha, min_alpha, _CMP_GE_OQ));
        if (_mm256_movemask_ps(valid) == 0) continue;
        const __m256 ra = _mm256_div_ps(one, _mm256_sub_ps(one, alpha));
        Tr = _mm256_blendv_ps(Tr, _mm256_mul_ps(Tr, ra), valid);
        const __m256 w = _mm256_and_ps(valid, _mm256_mul_ps(alpha, Tr));
        float* acc = scratch + static_cast<std::size_t>(k) * kFields * 8;
        const __m256 gr = _mm256_set1_ps(g.r), gg = _mm256_set1_ps(g.g), gb = _mm256_set1_ps(g.b);
        const __m256 gz = _mm256_set1_ps(g.z);
        acc_add(acc + 6 * 8, _mm256_mul_ps(w, vc0));
        acc_add(acc + 7 * 8, _mm256_mul_ps(w, vc1));
        acc_add(acc + 8 * 8, _mm256_mul_ps(w, vc2));
        acc_add(acc + 9 * 8, _mm256_mul_ps(w, vdd));
        __m256 v_a =
            _mm256_mul_ps(_mm256_sub_ps(_mm256_mul_ps(gr, Tr), _mm256_mul_ps(b0, ra)), vc0);
        v_a = _mm256_add_ps(
            v_a, _mm256_mul_ps(_mm256_sub_ps(_mm256_mul_ps(gg, Tr), _mm256_mul_ps(b1, ra)), vc1));
        v_a = _mm256_add_ps(
            v_a, _mm256_mul_ps(_mm256_sub_ps(_mm256_mul_ps(gb, Tr), _mm256_mul_ps(b2, ra)), vc2));
        v_a = _mm256_add_ps(
            v_a, _mm256_mul_ps(_mm256_sub_ps(_mm256_mul_ps(gz, Tr), _mm256_mul_ps(bd, ra)), vdd));
        v_a = _mm256_add_ps(v_a, _mm256_mul_ps(_mm256_mul_ps(Tf, ra), vaa));
        b0 = _mm256_add_ps(b0, _mm256_mul_ps(gr, w));
        b1 = _mm256_add_ps(b1, _mm256_mul_ps(gg, w));
        b2 = _mm256_add_ps(b2, _mm256_mul_ps(gb, w));
        bd = _mm256_add_ps(bd, _mm256_mul_ps(gz, w));
        const __m256 m2 = _mm256_and_ps(valid, _mm256_cmp_ps(raw, max_alpha, _CMP_LE_OQ));
        const __m256 v_sigma = _mm256_and_ps(m2, _mm256_sub_ps(zero, _mm256_mul_ps(raw, v_a)));
        const __m256 vdy = _mm256_set1_ps(dy);
        acc_add(acc + 2 * 8, _mm256_mul_ps(_mm256_mul_ps(half, _mm256_mul_ps(dx, dx)), v_sigma));
        acc_add(acc + 3 * 8, _mm256_mul_ps(_mm256_mul_ps(dx, vdy), v_sigma));
        acc_add(acc + 4 * 8, _mm256_mul_ps(_mm256_set1_ps(0.5f * dy * dy), v_sigma));
        const __m256 gx =
            _mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(g.ca), dx), _mm256_set1_ps(g.cb * dy));
        const __m256 gy =
            _mm256_add_ps(_mm256_mul_ps(_mm256_set1_ps(g.cb), dx), _mm256_set1_ps(g.cc * dy));
        acc_add(acc + 0 * 8, _mm256_mul_ps(v_sigma, gx));
        acc_add(acc + 1 * 8, _mm256_mul_ps(v_sigma, gy));
        acc_add(acc + 5 * 8, _mm256_and_ps(m2, _mm256_mul_ps(vis, v_a)));
      }
    }
  }
  for (int k = 0; k < count; ++k) {
    const float* acc = scratch + static_cast<std::size_t>(k) * kFields * 8;
    TileGrad<float>& g = grads[k];
    g.x += hsum(_mm256_loadu_ps(acc));
    g.y += hsum(_mm256_loadu_ps(acc + 8));
    g.ca += hsum(_mm256_loadu_ps(acc + 16));
    g.cb += hsum(_mm256_loadu_ps(acc + 24));
    g.cc += hsum(_mm256_loadu_ps(acc + 32));
    g.opacity += hsum(_mm256_loadu_ps(acc + 40));
    g.r += hsum(_mm256_loadu_ps(acc + 48));
    g.g += hsum(_mm256_loadu_ps(acc + 56));
    g.b += hsum(_mm256_loadu_ps(acc + 64));
    g.z += hsum(_mm256_loadu_ps(acc + 72));
  }
}

}  // namespace vigs::mapping
#endif
