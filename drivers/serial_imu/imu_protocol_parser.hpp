// ImuProtocolParser: the interface every serial IMU wire protocol implements.
//
// A parser is a resynchronising state machine fed with raw bytes in chunks of any size (one byte
// at a time gives the same result as the whole stream at once). Every complete, checksum-valid
// measurement becomes one DeviceImuSample handed to the sink, stamped only with the device's own
// sample counter; mapping that counter to host time is the driver's job (imu_stamper.hpp), so a
// protocol never touches the host clock.
//
// Real-time rules: feed() never allocates, locks, logs or throws; all buffers are members sized at
// construction. A second protocol (e.g. VectorNav binary) is one new parser file plus one line in
// parser_factory.cpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "drivers/serial_imu/parser_counters.hpp"

namespace vigs::drivers {

/// One measurement as the device sent it, in the IMU (sensor) frame.
struct DeviceImuSample {
  std::uint64_t device_ticks = 0;  ///< device sample counter as sent (wraps, see DeviceClockSpec)
  double gyro_rps[3] = {};         ///< angular rate, rad/s
  double accel_mps2[3] = {};       ///< specific force, m/s^2
};

/// How a protocol's sample counter counts.
struct DeviceClockSpec {
  double tick_hz = 0.0;       ///< counter increments per second of device time
  unsigned counter_bits = 0;  ///< the counter wraps at 2^counter_bits (1..64)
};

class ImuSampleSink {
 public:
  virtual ~ImuSampleSink() = default;
  virtual void on_sample(const DeviceImuSample& sample) noexcept = 0;
};

class ImuProtocolParser {
 public:
  virtual ~ImuProtocolParser() = default;

  /// Consumes `size` bytes. Complete samples go to `sink` in stream order, before feed() returns.
  /// Bytes of an unfinished message are kept for the next call.
  virtual void feed(const std::uint8_t* data, std::size_t size, ImuSampleSink& sink) noexcept = 0;

  /// Forgets any partial message (e.g. after reopening the port). Counters are kept.
  virtual void reset() noexcept = 0;

  /// Bytes held from an unfinished message (neither accepted nor skipped yet).
  [[nodiscard]] virtual std::size_t pending_bytes() const noexcept = 0;

  [[nodiscard]] virtual DeviceClockSpec clock() const noexcept = 0;
  [[nodiscard]] virtual std::string_view protocol_name() const noexcept = 0;
  [[nodiscard]] virtual const ParserCounters& counters() const noexcept = 0;
};

}  // namespace vigs::drivers
