// SerialBytes: up to 512 raw bytes exactly as one read() returned them from the IMU port, with
// the host time of that read. The serial driver's recorder tap carries these, so a recording
// holds the byte stream itself (vigs_msgs/SerialChunk) and a replay can feed the real driver
// the same bytes. A read longer than 512 bytes becomes several items with the same stamp.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace vigs::drivers {

struct SerialBytes {
  static constexpr std::size_t kCapacity = 512;
  SerialBytes() noexcept : data{} {}
  /// The first min(n, kCapacity) bytes of `bytes` (only those are written).
  SerialBytes(std::int64_t t, const std::uint8_t* bytes, std::size_t n) noexcept
      : t_ns(t), size(static_cast<std::uint16_t>(std::min(n, kCapacity))) {
    std::memcpy(data.data(), bytes, size);
  }

  std::int64_t t_ns = 0;  ///< CLOCK_MONOTONIC time of the read
  std::uint16_t size = 0;
  std::array<std::uint8_t, kCapacity> data;
};

}  // namespace vigs::drivers
