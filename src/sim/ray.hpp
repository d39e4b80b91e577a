#pragma once
// Rays and axis-aligned boxes in single precision (the renderer's hot path).
#include <algorithm>
#include <cmath>
#include <limits>

namespace vigs::sim {

struct Vec3f {
  float x = 0, y = 0, z = 0;
  float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};

inline Vec3f operator+(Vec3f a, Vec3f b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline Vec3f operator-(Vec3f a, Vec3f b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline Vec3f operator*(Vec3f a, float s) {
  return {a.x * s, a.y * s, a.z * s};
}
inline float dot(Vec3f a, Vec3f b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

/// Ray o + t d. `inv_d` is 1/d with zero components nudged so that slab tests stay finite.
struct Ray {
  Vec3f o;
  Vec3f d;
  Vec3f inv_d;
  static Ray make(Vec3f origin, Vec3f dir) {
    Ray r{origin, dir, {}};
    for (int i = 0; i < 3; ++i) {
      float c = dir[i];
      if (std::abs(c) < 1e-12f) c = c < 0 ? -1e-12f : 1e-12f;
      r.inv_d[i] = 1.0f / c;
    }
    return r;
  }
};

struct Aabb {
  Vec3f lo{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(),
           std::numeric_limits<float>::max()};
  Vec3f hi{-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max(),
           -std::numeric_limits<float>::max()};

  void grow(const Aabb& b) {
    lo = {std::min(lo.x, b.lo.x), std::min(lo.y, b.lo.y), std::min(lo.z, b.lo.z)};
    hi = {std::max(hi.x, b.hi.x), std::max(hi.y, b.hi.y), std::max(hi.z, b.hi.z)};
  }
  void grow(Vec3f p) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  [[nodiscard]] Vec3f center() const { return (lo + hi) * 0.5f; }
  [[nodiscard]] float area() const {
    const Vec3f e = hi - lo;
    if (e.x < 0) return 0.0f;
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
  }
};

/// Slab test: entry distance if the ray meets the box within (t_min, t_max), else +inf.
/// Written out per axis so that it compiles to straight-line min/max code.
inline float ray_box_entry(const Ray& r, const Aabb& b, float t_min, float t_max) {
  const float ax = (b.lo.x - r.o.x) * r.inv_d.x, bx = (b.hi.x - r.o.x) * r.inv_d.x;
  const float ay = (b.lo.y - r.o.y) * r.inv_d.y, by = (b.hi.y - r.o.y) * r.inv_d.y;
  const float az = (b.lo.z - r.o.z) * r.inv_d.z, bz = (b.hi.z - r.o.z) * r.inv_d.z;
  const float t0 =
      std::max(std::max(std::min(ax, bx), std::min(ay, by)), std::max(std::min(az, bz), t_min));
  const float t1 =
      std::min(std::min(std::max(ax, bx), std::max(ay, by)), std::min(std::max(az, bz), t_max));
  return t0 <= t1 ? t0 : std::numeric_limits<float>::infinity();
}

}  // namespace vigs::sim
