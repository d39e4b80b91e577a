// Xsens MT binary protocol (Xbus), as described in Xsens' public "MT Low Level Communication
// Protocol" documentation. Only what the parser and encoder need.
//
// Message:  PRE(0xFA) BID MID LEN [LENH LENL] DATA... CS
//  - LEN = 0xFF announces an extended length: two bytes, big-endian, follow.
//  - Checksum: the low byte of the sum of every byte after the preamble, checksum included, is 0.
// MTData2 (MID 0x36) data is a sequence of packets: data ID (2 bytes, big-endian), size (1 byte),
// then `size` bytes of big-endian values.
// Data ID bits: 0xF800 group, 0x00F0 type, 0x000C coordinate system (ENU/NED/NWU, the earth
// reference frame L), 0x0003 precision (float32, fixed 12.20, fixed 16.32, float64).
#pragma once

#include <cstddef>
#include <cstdint>

namespace vigs::drivers::xsens {

inline constexpr std::uint8_t kPreamble = 0xFA;
inline constexpr std::uint8_t kBusIdMaster = 0xFF;  ///< messages from a single MT device
inline constexpr std::uint8_t kMidMtData2 = 0x36;
inline constexpr std::uint8_t kExtendedLength = 0xFF;

inline constexpr std::size_t kHeaderSize = 4;          ///< PRE BID MID LEN
inline constexpr std::size_t kExtendedHeaderSize = 6;  ///< ... LENH LENL
inline constexpr std::size_t kMaxStandardDataSize = 254;
/// The parser never trusts a length above this (the LLCP caps extended messages at 2048 data
/// bytes; a full MTData2 configuration stays far below it).
inline constexpr std::size_t kMaxDataSize = 2048;
inline constexpr std::size_t kMaxMessageSize = kExtendedHeaderSize + kMaxDataSize + 1;

// Data IDs (precision and coordinate bits cleared).
inline constexpr std::uint16_t kIdSampleTimeFine = 0x1060;  ///< uint32, 10 kHz ticks
inline constexpr std::uint16_t kIdAcceleration = 0x4020;    ///< 3 values, m/s^2, sensor frame
inline constexpr std::uint16_t kIdRateOfTurn = 0x8020;      ///< 3 values, rad/s, sensor frame
inline constexpr std::uint16_t kTypeMask = 0xFFF0;
inline constexpr std::uint16_t kPrecisionMask = 0x0003;
inline constexpr std::uint16_t kCoordinateMask = 0x000C;

enum class Precision : std::uint16_t { kFloat32 = 0, kFixed1220 = 1, kFixed1632 = 2, kFloat64 = 3 };

inline constexpr double kSampleTimeFineHz = 10'000.0;

/// Checksum byte that makes the sum of `bytes` plus the checksum zero modulo 256.
[[nodiscard]] constexpr std::uint8_t checksum_of(const std::uint8_t* bytes,
                                                 std::size_t size) noexcept {
  std::uint8_t sum = 0;
  for (std::size_t i = 0; i < size; ++i) sum = static_cast<std::uint8_t>(sum + bytes[i]);
  return static_cast<std::uint8_t>(-sum);
}

}  // namespace vigs::drivers::xsens
