#pragma once
// Sorts one tile's Gaussians near to far: 64-bit keys whose high 32 bits are the depth's float
// bits (positive floats order as their bit patterns) and whose low 32 bits are the Gaussian's id.
//
// A least-significant-digit radix sort over the depth's four bytes, stable, so that keys that
// arrive in id order (as the rasterizer's tile lists do) come out ordered by (depth, id): the
// order std::sort gives the whole keys. Hand-written rather than boost's spreadsort because a
// tile holds tens to a few thousand Gaussians, where spreadsort falls back to std::sort; here the
// bytes that every key of the tile shares (the exponent, mostly) cost one histogram and no pass.
#include <cstddef>
#include <cstdint>
#include <utility>

namespace vigs::mapping {

/// Below this many keys an insertion sort is faster than the histograms.
inline constexpr std::size_t kDepthKeyInsertionSortMax = 48;

/// Sorts keys[0, n) by their high 32 bits, stably; `scratch` holds n keys. The result is in keys.
inline void sort_depth_keys(std::uint64_t* keys, std::uint64_t* scratch, std::size_t n) {
  if (n <= kDepthKeyInsertionSortMax) {
    for (std::size_t i = 1; i < n; ++i) {
      const std::uint64_t k = keys[i];
      const std::uint32_t d = static_cast<std::uint32_t>(k >> 32);
      std::size_t j = i;
      for (; j > 0 && static_cast<std::uint32_t>(keys[j - 1] >> 32) > d; --j) keys[j] = keys[j - 1];
      keys[j] = k;
    }
    return;
  }
  std::uint32_t count[4][256] = {};
  for (std::size_t i = 0; i < n; ++i) {
    const auto d = static_cast<std::uint32_t>(keys[i] >> 32);
    ++count[0][d & 0xffu];
    ++count[1][(d >> 8) & 0xffu];
    ++count[2][(d >> 16) & 0xffu];
    ++count[3][d >> 24];
  }
  std::uint64_t* src = keys;
  std::uint64_t* dst = scratch;
  for (int pass = 0; pass < 4; ++pass) {
    std::uint32_t* c = count[pass];
    const int shift = 32 + 8 * pass;
    if (c[(src[0] >> shift) & 0xffu] == n) continue;  // every key shares this byte
    std::uint32_t at = 0;
    for (int b = 0; b < 256; ++b) {
      const std::uint32_t here = c[b];
      c[b] = at;
      at += here;
    }
    for (std::size_t i = 0; i < n; ++i) dst[c[(src[i] >> shift) & 0xffu]++] = src[i];
    std::swap(src, dst);
  }
  if (src != keys)
    for (std::size_t i = 0; i < n; ++i) keys[i] = src[i];
}

}  // namespace vigs::mapping
