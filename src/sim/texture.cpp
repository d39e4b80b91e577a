#include "sim/texture.hpp"

#include <algorithm>
#include <cmath>

namespace vigs::sim {
namespace {

inline std::uint32_t hash2(std::int32_t x, std::int32_t y, std::uint32_t seed) {
  std::uint32_t h = seed ^ 0x9E3779B9u;
  h ^= static_cast<std::uint32_t>(x) * 0x85EBCA6Bu;
  h = (h << 13) | (h >> 19);
  h ^= static_cast<std::uint32_t>(y) * 0xC2B2AE35u;
  h *= 0x27D4EB2Fu;
  h ^= h >> 15;
  h *= 0x85EBCA6Bu;
  h ^= h >> 13;
  return h;
}

inline float unit(std::uint32_t h) {
  return static_cast<float>(h >> 8) * (1.0f / 16777216.0f);
}

inline float fract(float x) {
  return x - std::floor(x);
}

inline Rgb mix(Rgb a, Rgb b, float t) {
  return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}
inline Rgb scale(Rgb a, float s) {
  return {a.r * s, a.g * s, a.b * s};
}

/// A muted palette colour picked by hash.
Rgb palette(std::uint32_t h) {
  static const Rgb kColors[] = {{0.85f, 0.82f, 0.74f}, {0.70f, 0.78f, 0.83f}, {0.80f, 0.72f, 0.66f},
                                {0.74f, 0.80f, 0.70f}, {0.88f, 0.86f, 0.82f}, {0.66f, 0.68f, 0.78f},
                                {0.82f, 0.78f, 0.60f}, {0.76f, 0.70f, 0.76f}};
  return kColors[h % 8u];
}

Rgb vivid(std::uint32_t h) {
  return {0.15f + 0.8f * unit(h), 0.15f + 0.8f * unit(h * 747796405u + 1u),
          0.15f + 0.8f * unit(h * 2891336453u + 7u)};
}

/// Two octaves of detail noise centred on 1. The fine octave (23 cycles per metre) fades to
/// its mean where a pixel covers more than a quarter of its period (gone at half a period,
/// the Nyquist limit), so distant and grazing surfaces do not alias into view-dependent
/// speckle. `footprint` is the pixel's size on the surface in noise units (metres here).
inline float detail(float u, float v, std::uint32_t seed, float amp, float footprint) {
  const float cycles_per_pixel = 23.0f * footprint;
  const float w = std::clamp((0.5f - cycles_per_pixel) * 4.0f, 0.0f, 1.0f);
  const float fine = w > 0.0f ? value_noise(u * 23.0f, v * 23.0f, seed + 17u) : 0.5f;
  const float n =
      0.65f * value_noise(u * 4.0f, v * 4.0f, seed) + 0.35f * (0.5f + w * (fine - 0.5f));
  return 1.0f + amp * (2.0f * n - 1.0f);
}

}  // namespace

float value_noise(float x, float y, std::uint32_t seed) {
  const float fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int32_t>(fx), iy = static_cast<std::int32_t>(fy);
  float tx = x - fx, ty = y - fy;
  tx = tx * tx * (3.0f - 2.0f * tx);
  ty = ty * ty * (3.0f - 2.0f * ty);
  const float a = unit(hash2(ix, iy, seed)), b = unit(hash2(ix + 1, iy, seed));
  const float c = unit(hash2(ix, iy + 1, seed)), d = unit(hash2(ix + 1, iy + 1, seed));
  return (a + (b - a) * tx) + ((c + (d - c) * tx) - (a + (b - a) * tx)) * ty;
}

Rgb albedo(Material material, std::uint32_t tint, float u, float v, float fp) {
  switch (material) {
    case Material::kFloor: {  // 0.6 m tiles, per-tile shade, dark grout, speckle
      const float tu = u / 0.6f, tv = v / 0.6f;
      const auto ix = static_cast<std::int32_t>(std::floor(tu));
      const auto iy = static_cast<std::int32_t>(std::floor(tv));
      if (fract(tu) < 0.03f || fract(tv) < 0.03f) return {0.25f, 0.24f, 0.22f};
      const float shade = 0.8f + 0.25f * unit(hash2(ix, iy, 11u));
      const Rgb base =
          mix({0.55f, 0.52f, 0.47f}, {0.42f, 0.45f, 0.50f}, value_noise(u * 0.15f, v * 0.15f, 3u));
      return scale(base, shade * detail(u, v, 5u, 0.18f, fp));
    }
    case Material::kCeiling: {  // 0.6 m panels and light panels every 2.4 m
      const float lu = fract(u / 2.4f), lv = fract(v / 2.4f);
      if (lu > 0.25f && lu < 0.75f && lv > 0.375f && lv < 0.625f) return {0.98f, 0.97f, 0.92f};
      if (fract(u / 0.6f) < 0.03f || fract(v / 0.6f) < 0.03f) return {0.45f, 0.45f, 0.45f};
      return scale({0.80f, 0.80f, 0.78f}, detail(u, v, 7u, 0.12f, fp));
    }
    case Material::kWall: {
      if (v < 0.1f) return {0.30f, 0.27f, 0.25f};  // skirting board
      // Posters: one chance per 1.6 m of wall, 0.9 m x 1.0 m between 1.0 and 2.0 m high.
      const float cu = u / 1.6f;
      const auto cell = static_cast<std::int32_t>(std::floor(cu));
      const std::uint32_t ph = hash2(cell, 0, tint);
      const float pu = fract(cu) * 1.6f;
      if (unit(ph) < 0.45f && pu > 0.35f && pu < 1.25f && v > 1.0f && v < 2.0f) {
        const auto bx = static_cast<std::int32_t>(std::floor(u / 0.15f));
        const auto by = static_cast<std::int32_t>(std::floor(v / 0.15f));
        const Rgb block = vivid(hash2(bx, by, ph));
        return scale(block, detail(u, v, ph, 0.10f, fp));
      }
      const Rgb base = palette(tint);
      const float stain = 0.88f + 0.24f * value_noise(u * 0.8f, v * 0.8f, tint);
      return scale(base, stain * detail(u, v, tint + 3u, 0.10f, fp));
    }
    case Material::kWood: {
      const float grain =
          0.5f + 0.5f * std::sin(u * 35.0f + 6.0f * value_noise(u * 2.0f, v * 9.0f, tint));
      return scale(mix({0.55f, 0.36f, 0.20f}, {0.40f, 0.25f, 0.13f}, grain),
                   detail(u, v, tint, 0.08f, fp));
    }
    case Material::kMetal:
      return scale({0.58f, 0.60f, 0.62f}, detail(u * 0.2f, v * 6.0f, tint, 0.12f, 6.0f * fp));
    case Material::kFabric:
      return scale(vivid(tint), 0.6f * detail(u, v, tint, 0.2f, fp));
    case Material::kScreen: {
      const auto bx = static_cast<std::int32_t>(std::floor(u / 0.05f));
      const auto by = static_cast<std::int32_t>(std::floor(v / 0.04f));
      const float on = unit(hash2(bx, by, tint)) < 0.4f ? 1.0f : 0.15f;
      return {0.1f + 0.5f * on, 0.15f + 0.6f * on, 0.2f + 0.7f * on};
    }
    case Material::kSkin:
      return scale({0.78f, 0.60f, 0.50f}, detail(u, v, tint, 0.06f, fp));
    case Material::kCloth: {
      const float stripe = fract(v / 0.12f) < 0.5f ? 1.0f : 0.7f;
      return scale(vivid(tint), stripe * detail(u, v, tint, 0.15f, fp));
    }
  }
  return {1.0f, 0.0f, 1.0f};
}

}  // namespace vigs::sim
