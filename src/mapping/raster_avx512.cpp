// AVX-512 forward blending kernel: sixteen pixels per vector, a block of 8 columns by 2 rows of a
// tile, one Gaussian broadcast at a time, with per-lane termination masks. The same arithmetic as
// the AVX2 kernel (raster_avx2.cpp, 8 pixels of one row per vector), twice the lanes. A block
// two rows tall rather than a whole 16-pixel row: the Gaussians of a half-resolution view (most
// of the live mapper's iterations) are a few pixels wide, and more of them reach all of a compact
// block than all of a long row, so fewer lanes idle (the lockstep office replay's mapper time per
// frame: AVX2 32.8 ms, 16-pixel rows 28.7 ms, these blocks 25.0 ms; BENCHMARKS.md, the
// thirty-fifth session). Compiled with -mavx512f -mavx512dq -mfma and only called after the
// run-time check in raster_simd.cpp.
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>

#include <algorithm>
#include <cstdint>

#include "mapping/avx512_math.hpp"
#include "mapping/raster_simd.hpp"

namespace vigs::mapping {

namespace {

/// Whether Gaussian g can reach block b of `rect`: out_of_reach() false for one of its rows over
/// its columns.
bool reaches_block(const TileGaussian<float>& g, const TileRect& rect, int b) {
  const PixelBlock pb = tile_block(rect, b);
  const auto x0 = static_cast<float>(pb.x0), x1 = static_cast<float>(pb.x0 + pb.w - 1);
  for (int y = pb.y0; y < pb.y0 + pb.h; ++y)
    if (!out_of_reach(g, x0, x1, static_cast<float>(y))) return true;
  return false;
}

/// The per-block test written out one Gaussian and block at a time: for tiles taller than 32
/// rows or wider than 16 columns, which the bit masks below cannot hold.
void fill_tile_blocks_each(const TileRect& rect, const TileGaussian<float>* gs, int count,
                           int* blocks) {
  const int n_blocks = tile_blocks(rect);
  int* sizes = blocks;
  int* lists = blocks + n_blocks;
  for (int b = 0; b < n_blocks; ++b) sizes[b] = 0;
  for (int k = 0; k < count; ++k)
    for (int b = 0; b < n_blocks; ++b) {
      lists[b * count + sizes[b]] = k;
      sizes[b] += reaches_block(gs[k], rect, b) ? 1 : 0;
    }
}

}  // namespace

void fill_tile_blocks_avx512(const TileRect& rect, const TileGaussian<float>* gs, int count,
                             int* blocks) {
  const int rows = rect.y1 - rect.y0, cols = (rect.x1 - rect.x0 + 7) / 8;
  if (rows > 32 || cols > 2) {
    fill_tile_blocks_each(rect, gs, count, blocks);
    return;
  }
  // out_of_reach() is a row test or a column test, so a Gaussian reaches block (pair, column)
  // exactly when it reaches one of the pair's rows and the block's columns. Each Gaussian's rows
  // and columns become bit masks (the same float comparisons, 16 rows per vector), and each
  // block's list is compressed 16 Gaussians at a time from the masks.
  const int n_blocks = tile_blocks(rect), pairs = (rows + 1) / 2;
  const int padded = (count + 15) & ~15;
  int* sizes = blocks;
  int* lists = blocks + n_blocks;
  auto* row_bits = reinterpret_cast<std::uint32_t*>(lists + n_blocks * count + 16);
  std::uint32_t* col_bits = row_bits + padded;
  const __m512 sign = _mm512_set1_ps(-0.0f);
  const __m512 lane = _mm512_setr_ps(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  const int row_vectors = (rows + 15) / 16;
  __m512 fy[2] = {_mm512_setzero_ps(), _mm512_setzero_ps()};
  for (int v = 0; v < row_vectors; ++v)
    fy[v] = _mm512_add_ps(_mm512_set1_ps(static_cast<float>(rect.y0 + 16 * v)), lane);
  const std::uint32_t all_rows = rows == 32 ? 0xffffffffu : (1u << rows) - 1u;
  for (int k = 0; k < count; ++k) {
    const TileGaussian<float>& g = gs[k];
    const __m512 gy = _mm512_set1_ps(g.y), reach_y = _mm512_set1_ps(g.reach_y);
    std::uint32_t out = 0;
    for (int v = 0; v < row_vectors; ++v) {
      const __m512 ady = _mm512_andnot_ps(sign, _mm512_sub_ps(gy, fy[v]));
      out |= static_cast<std::uint32_t>(_mm512_cmp_ps_mask(ady, reach_y, _CMP_GT_OQ)) << (16 * v);
    }
    row_bits[k] = ~out & all_rows;
    std::uint32_t c_bits = 0;
    for (int c = 0; c < cols; ++c) {
      const int x0 = rect.x0 + 8 * c, x1 = std::min(x0 + 8, rect.x1) - 1;
      const bool miss =
          g.x + g.reach_x < static_cast<float>(x0) || g.x - g.reach_x > static_cast<float>(x1);
      c_bits |= miss ? 0u : (1u << c);
    }
    col_bits[k] = c_bits;
  }
  for (int k = count; k < padded; ++k) row_bits[k] = col_bits[k] = 0;
  const __m512i iota = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
  for (int pair = 0; pair < pairs; ++pair) {
    const __m512i pair_bits = _mm512_set1_epi32(static_cast<int>(3u << (2 * pair)));
    for (int c = 0; c < cols; ++c) {
      const int block = pair * cols + c;
      const __m512i col_bit = _mm512_set1_epi32(static_cast<int>(1u << c));
      int* list = lists + block * count;
      int n = 0;
      for (int k = 0; k < padded; k += 16) {
        const __mmask16 hit = _mm512_mask_test_epi32_mask(
            _mm512_test_epi32_mask(_mm512_loadu_si512(row_bits + k), pair_bits),
            _mm512_loadu_si512(col_bits + k), col_bit);
        if (hit == 0) continue;
        // the store may write up to 15 ints past the list's end, into the next block's list
        // (filled after this one) or the padding that tile_block_scratch() leaves after the last
        _mm512_storeu_si512(list + n, _mm512_maskz_compress_epi32(
                                          hit, _mm512_add_epi32(iota, _mm512_set1_epi32(k))));
        n += __builtin_popcount(static_cast<unsigned>(hit));
      }
      sizes[block] = n;
    }
  }
}

void forward_tile_avx512(const TileRect& rect, const TileGaussian<float>* gs, int count,
                         const RasterSettings& s, PixelOutputs<float>& out, int* blocks) {
  const __m512 min_alpha = _mm512_set1_ps(static_cast<float>(s.min_alpha));
  const __m512 max_alpha = _mm512_set1_ps(static_cast<float>(s.max_alpha));
  const __m512 min_T = _mm512_set1_ps(static_cast<float>(s.min_transmittance));
  const __m512 one = _mm512_set1_ps(1.0f), zero = _mm512_setzero_ps();
  const __m512 lane_x = avx512::block_lane_x(), lane_y = avx512::block_lane_y();
  fill_tile_blocks_avx512(rect, gs, count, blocks);
  const int n_blocks = tile_blocks(rect);
  for (int block = 0; block < n_blocks; ++block) {
    const PixelBlock pb = tile_block(rect, block);
    const unsigned row_mask = (1u << pb.w) - 1u;
    // lanes beyond the tile's edge start finished
    const auto in_block = static_cast<__mmask16>(row_mask | (pb.h == 2 ? row_mask << 8 : 0u));
    const __m512 px = _mm512_add_ps(_mm512_set1_ps(static_cast<float>(pb.x0)), lane_x);
    const __m512 py = _mm512_add_ps(_mm512_set1_ps(static_cast<float>(pb.y0)), lane_y);
    const int* list = blocks + n_blocks + block * count;
    const int n_list = blocks[block];
    __m512 Tr = one, c0 = zero, c1 = zero, c2 = zero, d = zero, last = zero;
    __mmask16 live = in_block;
    for (int j = 0; j < n_list; ++j) {
      const int k = list[j];
      const TileGaussian<float>& g = gs[k];
      const __m512 dx = _mm512_sub_ps(_mm512_set1_ps(g.x), px);
      const __m512 dy = _mm512_sub_ps(_mm512_set1_ps(g.y), py);
      const __m512 sigma = avx512::conic_sigma(g.ca, g.cb, g.cc, dx, dy);
      __mmask16 valid = _mm512_mask_cmp_ps_mask(live, sigma, zero, _CMP_GE_OQ);
      valid = _mm512_mask_cmp_ps_mask(valid, sigma, _mm512_set1_ps(g.sigma_cut), _CMP_LE_OQ);
      if (valid == 0) continue;
      const __m512 vis = avx512::exp_neg_ps(_mm512_sub_ps(zero, sigma));
      const __m512 alpha = _mm512_min_ps(max_alpha, _mm512_mul_ps(_mm512_set1_ps(g.opacity), vis));
      valid = _mm512_mask_cmp_ps_mask(valid, alpha, min_alpha, _CMP_GE_OQ);
      const __m512 next_T = _mm512_mul_ps(Tr, _mm512_sub_ps(one, alpha));
      const __mmask16 stop = _mm512_mask_cmp_ps_mask(valid, next_T, min_T, _CMP_LE_OQ);
      live = static_cast<__mmask16>(live & ~stop);
      const auto take = static_cast<__mmask16>(valid & ~stop);
      const __m512 wt = _mm512_maskz_mul_ps(take, alpha, Tr);
      c0 = _mm512_add_ps(c0, _mm512_mul_ps(wt, _mm512_set1_ps(g.r)));
      c1 = _mm512_add_ps(c1, _mm512_mul_ps(wt, _mm512_set1_ps(g.g)));
      c2 = _mm512_add_ps(c2, _mm512_mul_ps(wt, _mm512_set1_ps(g.b)));
      d = _mm512_add_ps(d, _mm512_mul_ps(wt, _mm512_set1_ps(g.z)));
      Tr = _mm512_mask_mov_ps(Tr, take, next_T);
      last = _mm512_mask_mov_ps(last, take, _mm512_set1_ps(static_cast<float>(k + 1)));
      if (live == 0) break;
    }
    alignas(64) float bc0[16], bc1[16], bc2[16], bd[16], bT[16];
    alignas(64) int bl[16];
    _mm512_store_ps(bc0, c0);
    _mm512_store_ps(bc1, c1);
    _mm512_store_ps(bc2, c2);
    _mm512_store_ps(bd, d);
    _mm512_store_ps(bT, Tr);
    _mm512_store_si512(bl, _mm512_cvttps_epi32(last));
    for (int r = 0; r < pb.h; ++r)
      for (int l = 0; l < pb.w; ++l) {
        const int p = (pb.y0 + r) * out.width + pb.x0 + l, i = 8 * r + l;
        out.color[3 * p] = bc0[i];
        out.color[3 * p + 1] = bc1[i];
        out.color[3 * p + 2] = bc2[i];
        out.depth[p] = bd[i];
        out.final_T[p] = bT[i];
        out.n_contrib[p] = bl[i];
      }
  }
}

}  // namespace vigs::mapping
#endif
