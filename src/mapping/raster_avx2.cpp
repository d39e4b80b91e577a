// AVX2 forward blending kernel: 8 pixels of a tile row per vector, one Gaussian broadcast at a
// time, with per-lane termination masks. Compiled with -mavx2 -mfma and only called after the
// run-time check in raster_simd.cpp. The arithmetic follows the scalar kernel's order (no fused
// multiply-add in the decisions) and exp is a Cephes-style polynomial (about 1 ulp), so images
// agree with the scalar path to well within 1e-5.
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include <algorithm>
#include <cstdint>

#include "mapping/avx2_math.hpp"
#include "mapping/raster_simd.hpp"

namespace vigs::mapping {

namespace {

/// For each 8-bit mask, the positions of its set bits, low to high, one per nibble: the
/// permutation that packs the selected lanes of a vector to its front.
struct LeftPackTable {
  std::uint32_t nibbles[256];
  constexpr LeftPackTable() : nibbles{} {
    for (int m = 0; m < 256; ++m) {
      std::uint32_t packed = 0;
      int n = 0;
      for (int b = 0; b < 8; ++b)
        if (m & (1 << b)) packed |= static_cast<std::uint32_t>(b) << (4 * n++);
      nibbles[m] = packed;
    }
  }
};
constexpr LeftPackTable kLeftPack;

/// The per-run test written out one Gaussian and run at a time: for tiles taller than 32 rows
/// or wider than 32 runs, which the row and column bit masks below cannot hold.
void fill_tile_runs_each(const TileRect& rect, const TileGaussian<float>* gs, int count,
                         int* runs) {
  const int n_runs = tile_runs(rect);
  int* sizes = runs;
  int* lists = runs + n_runs;
  for (int r = 0; r < n_runs; ++r) sizes[r] = 0;
  for (int k = 0; k < count; ++k) {
    int run = 0;
    for (int py = rect.y0; py < rect.y1; ++py)
      for (int x0 = rect.x0; x0 < rect.x1; x0 += 8, ++run) {
        const int x1 = x0 + std::min(8, rect.x1 - x0) - 1;
        const bool reach = !out_of_reach(gs[k], static_cast<float>(x0), static_cast<float>(x1),
                                         static_cast<float>(py));
        lists[run * count + sizes[run]] = k;
        sizes[run] += reach ? 1 : 0;
      }
  }
}

}  // namespace

void fill_tile_runs_avx2(const TileRect& rect, const TileGaussian<float>* gs, int count,
                         int* runs) {
  const int rows = rect.y1 - rect.y0, cols = (rect.x1 - rect.x0 + 7) / 8;
  if (rows > 32 || cols > 32) {
    fill_tile_runs_each(rect, gs, count, runs);
    return;
  }
  // out_of_reach() is a row test (|dy| > reach_y) or a column test (the x extents miss the
  // run's), so a Gaussian reaches run (row, column) exactly when it reaches both. Each
  // Gaussian's rows and columns become bit masks (the same float comparisons, 8 rows per
  // vector), and each run's list is then packed 8 Gaussians at a time from the masks. Testing
  // and writing every run for every Gaussian one at a time took a third as long as the blending.
  const int n_runs = rows * cols;
  const int padded = (count + 7) & ~7;
  int* sizes = runs;
  int* lists = runs + n_runs;
  auto* row_bits = reinterpret_cast<std::uint32_t*>(lists + n_runs * count + 8);
  std::uint32_t* col_bits = row_bits + padded;
  const __m256 sign = _mm256_set1_ps(-0.0f);
  const __m256 lane = _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7);
  const int row_vectors = (rows + 7) / 8;
  __m256 fy[4];
  for (int v = 0; v < row_vectors; ++v)
    fy[v] = _mm256_add_ps(_mm256_set1_ps(static_cast<float>(rect.y0 + 8 * v)), lane);
  const std::uint32_t all_rows = rows == 32 ? 0xffffffffu : (1u << rows) - 1u;
  for (int k = 0; k < count; ++k) {
    const TileGaussian<float>& g = gs[k];
    const __m256 gy = _mm256_set1_ps(g.y), reach_y = _mm256_set1_ps(g.reach_y);
    std::uint32_t out = 0;
    for (int v = 0; v < row_vectors; ++v) {
      const __m256 ady = _mm256_andnot_ps(sign, _mm256_sub_ps(gy, fy[v]));
      out |= static_cast<std::uint32_t>(_mm256_movemask_ps(_mm256_cmp_ps(ady, reach_y, _CMP_GT_OQ)))
             << (8 * v);
    }
    row_bits[k] = ~out & all_rows;
    std::uint32_t c_bits = 0;
    for (int c = 0; c < cols; ++c) {
      const int x0 = rect.x0 + 8 * c, x1 = x0 + std::min(8, rect.x1 - x0) - 1;
      const bool miss =
          g.x + g.reach_x < static_cast<float>(x0) || g.x - g.reach_x > static_cast<float>(x1);
      c_bits |= miss ? 0u : (1u << c);
    }
    col_bits[k] = c_bits;
  }
  for (int k = count; k < padded; ++k) row_bits[k] = col_bits[k] = 0;
  const __m256i zero = _mm256_setzero_si256();
  const __m256i nibble_shift = _mm256_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28);
  const __m256i nibble = _mm256_set1_epi32(0xF);
  for (int row = 0; row < rows; ++row) {
    const __m256i row_bit = _mm256_set1_epi32(static_cast<int>(1u << row));
    for (int c = 0; c < cols; ++c) {
      const int run = row * cols + c;
      const __m256i col_bit = _mm256_set1_epi32(static_cast<int>(1u << c));
      int* list = lists + run * count;
      int n = 0;
      for (int k = 0; k < padded; k += 8) {
        const __m256i rb = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(row_bits + k));
        const __m256i cb = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(col_bits + k));
        const __m256i miss =
            _mm256_or_si256(_mm256_cmpeq_epi32(_mm256_and_si256(rb, row_bit), zero),
                            _mm256_cmpeq_epi32(_mm256_and_si256(cb, col_bit), zero));
        const int hit = ~_mm256_movemask_ps(_mm256_castsi256_ps(miss)) & 0xFF;
        if (hit == 0) continue;
        // lanes k + (positions of the set bits), packed to the front; the store may write up to
        // 7 ints past the list's end, into the next run's list (filled after this one) or the
        // padding that tile_run_scratch() leaves after the last
        const __m256i perm = _mm256_and_si256(
            _mm256_srlv_epi32(_mm256_set1_epi32(static_cast<int>(kLeftPack.nibbles[hit])),
                              nibble_shift),
            nibble);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(list + n),
                            _mm256_add_epi32(perm, _mm256_set1_epi32(k)));
        n += __builtin_popcount(static_cast<unsigned>(hit));
      }
      sizes[run] = n;
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
