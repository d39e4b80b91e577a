#pragma once
#include <cstddef>
#include <cstdint>
#include <span>

namespace vigs::io::mcap {

/// CRC-32 (zlib's crc32) with the IEEE 802.3 polynomial (reflected 0xEDB88320, init and final xor
/// 0xFFFFFFFF), as MCAP uses. Incremental: crc32_update(crc32_update(0, a), b) == crc32(a + b).
std::uint32_t crc32_update(std::uint32_t crc, std::span<const std::uint8_t> bytes);
inline std::uint32_t crc32(std::span<const std::uint8_t> bytes) {
  return crc32_update(0, bytes);
}

}  // namespace vigs::io::mcap
