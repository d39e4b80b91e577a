// Big-endian loads and stores for wire formats. memcpy-based: no alignment or aliasing issues,
// and compilers turn each into one load plus a byte swap.
#pragma once

#include <bit>
#include <cstdint>
#include <cstring>

namespace vigs::drivers {

[[nodiscard]] inline std::uint16_t load_be_u16(const std::uint8_t* p) noexcept {
  return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
}

[[nodiscard]] inline std::uint32_t load_be_u32(const std::uint8_t* p) noexcept {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

[[nodiscard]] inline std::uint64_t load_be_u64(const std::uint8_t* p) noexcept {
  return (std::uint64_t{load_be_u32(p)} << 32) | load_be_u32(p + 4);
}

[[nodiscard]] inline float load_be_f32(const std::uint8_t* p) noexcept {
  return std::bit_cast<float>(load_be_u32(p));
}

[[nodiscard]] inline double load_be_f64(const std::uint8_t* p) noexcept {
  return std::bit_cast<double>(load_be_u64(p));
}

inline void store_be_u16(std::uint8_t* p, std::uint16_t v) noexcept {
  p[0] = static_cast<std::uint8_t>(v >> 8);
  p[1] = static_cast<std::uint8_t>(v);
}

inline void store_be_u32(std::uint8_t* p, std::uint32_t v) noexcept {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<std::uint8_t>(v >> (24 - 8 * i));
}

inline void store_be_u64(std::uint8_t* p, std::uint64_t v) noexcept {
  store_be_u32(p, static_cast<std::uint32_t>(v >> 32));
  store_be_u32(p + 4, static_cast<std::uint32_t>(v));
}

inline void store_be_f32(std::uint8_t* p, float v) noexcept {
  store_be_u32(p, std::bit_cast<std::uint32_t>(v));
}

inline void store_be_f64(std::uint8_t* p, double v) noexcept {
  store_be_u64(p, std::bit_cast<std::uint64_t>(v));
}

}  // namespace vigs::drivers
