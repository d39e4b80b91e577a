// Encoder for Xsens MT binary messages: the exact inverse of XsensMtParser for the fields it
// decodes. Used by tests, benchmarks, and the recorder / replay feeder to produce wire bytes.
// Allocates (returns std::vector): not for real-time threads.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "drivers/serial_imu/xsens_mt.hpp"

namespace vigs::drivers::xsens {

/// A complete Xbus message: preamble, bus id 0xFF, `mid`, length (extended when the data is
/// longer than 254 bytes), data, checksum. Throws std::length_error above kMaxDataSize.
[[nodiscard]] std::vector<std::uint8_t> encode_message(std::uint8_t mid,
                                                       std::span<const std::uint8_t> data);

/// Appends one MTData2 packet (data ID, size byte, bytes) to an MTData2 payload. Throws
/// std::length_error when `bytes` is longer than 255.
void append_packet(std::vector<std::uint8_t>& payload, std::uint16_t data_id,
                   std::span<const std::uint8_t> bytes);

/// Appends a 3-vector packet in `precision` (float32, fixed 12.20 or float64); `type_id` is
/// kIdAcceleration or kIdRateOfTurn.
void append_vec3(std::vector<std::uint8_t>& payload, std::uint16_t type_id,
                 const std::array<double, 3>& v, Precision precision);

/// MTData2 message with SampleTimeFine, Acceleration and RateOfTurn, in that order.
[[nodiscard]] std::vector<std::uint8_t> encode_mtdata2(std::uint32_t sample_time_fine,
                                                       const std::array<double, 3>& accel_mps2,
                                                       const std::array<double, 3>& gyro_rps,
                                                       Precision precision = Precision::kFloat32);

}  // namespace vigs::drivers::xsens
