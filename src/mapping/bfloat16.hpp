#pragma once
// bfloat16 storage: the upper 16 bits of an IEEE float (8-bit exponent, 7-bit mantissa), so the
// float's range with about 2-3 significant digits. Used for Adam's first moment
// (adam.hpp), an exponential average whose per-step change (1 - beta1 = 10 %) is far above its
// rounding (0.4 %), as 8-bit and 16-bit optimiser states are in large-model training. Not for
// the second moment: its per-step change (1 - beta2 = 0.1 %) is below bfloat16's resolution, so
// it would never decay. Hand-written because no Debian library offers a scalar conversion
// (C++23's std::bfloat16_t is not in GCC 12's C++20).
#include <bit>
#include <cmath>
#include <cstdint>

namespace vigs::mapping {

/// Round to nearest, ties to even; NaN stays a (quiet) NaN.
inline std::uint16_t to_bfloat16(float f) {
  if (std::isnan(f)) return 0x7FC0u;
  std::uint32_t u = std::bit_cast<std::uint32_t>(f);
  u += 0x7FFFu + ((u >> 16) & 1u);
  return static_cast<std::uint16_t>(u >> 16);
}

inline float from_bfloat16(std::uint16_t b) {
  return std::bit_cast<float>(static_cast<std::uint32_t>(b) << 16);
}

}  // namespace vigs::mapping
