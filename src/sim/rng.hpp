#pragma once
// Counter-based random numbers (SplitMix64 finaliser): a value depends only on (seed, stream,
// index), so results do not depend on thread scheduling or call order. Normals use
// Box-Muller on two such uniforms; no std:: distribution is used, so sequences are the same
// with every standard library.
#include <cmath>
#include <cstdint>

namespace vigs::sim {

inline std::uint64_t mix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

inline std::uint64_t hash3(std::uint64_t a, std::uint64_t b, std::uint64_t c) {
  return mix64(mix64(mix64(a) ^ b) ^ c);
}

/// Uniform in [0, 1) with 53 random bits.
inline double to_unit(std::uint64_t h) {
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

/// Standard normal from two independent 64-bit hashes.
inline double normal_from(std::uint64_t h1, std::uint64_t h2) {
  const double u1 = 1.0 - to_unit(h1);  // (0, 1]
  const double u2 = to_unit(h2);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

/// Approximately standard normal from one 64-bit hash: the sum of four 16-bit uniforms
/// (Irwin-Hall), rescaled to unit variance; bounded by +-3.46. Cheap enough per pixel.
inline float fast_normal_from(std::uint64_t h) {
  const auto sum =
      static_cast<float>((h & 0xFFFF) + ((h >> 16) & 0xFFFF) + ((h >> 32) & 0xFFFF) + (h >> 48));
  return (sum * (1.0f / 65536.0f) - 2.0f) * 1.7320508f;
}

/// Sequential generator for one stream (IMU noise, scene layout).
class Rng {
 public:
  Rng(std::uint64_t seed, std::uint64_t stream) : seed_(seed), stream_(stream) {}
  std::uint64_t next_u64() { return hash3(seed_, stream_, counter_++); }
  double uniform() { return to_unit(next_u64()); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  int uniform_int(int lo, int hi_inclusive) {
    return lo + static_cast<int>(next_u64() % static_cast<std::uint64_t>(hi_inclusive - lo + 1));
  }
  double normal() {
    const std::uint64_t a = next_u64();
    return normal_from(a, next_u64());
  }

 private:
  std::uint64_t seed_;
  std::uint64_t stream_;
  std::uint64_t counter_ = 0;
};

}  // namespace vigs::sim
