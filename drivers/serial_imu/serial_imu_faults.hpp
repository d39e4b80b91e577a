// SerialImuFaults: a plain snapshot of every serial IMU driver counter, one per kind of fault,
// for the exit report (`vigs`) and the status topic. to_json() gives one JSON object,
// to_string() a single "name=value ..." line.
#pragma once

#include <cstdint>
#include <string>

#include "io/json_text.hpp"

namespace vigs::drivers {

struct ParserCounters;
struct StamperCounters;

struct SerialImuFaults {
  // Progress.
  std::uint64_t bytes_read = 0;   ///< bytes returned by read()
  std::uint64_t packets_ok = 0;   ///< valid measurement messages
  std::uint64_t samples_out = 0;  ///< stamped samples offered to the ring
  // Faults, one counter per kind.
  std::uint64_t bad_checksum = 0;
  std::uint64_t resync_bytes_skipped = 0;
  std::uint64_t oversize_length = 0;
  std::uint64_t sample_counter_gap = 0;
  std::uint64_t samples_missed = 0;  ///< samples skipped by those gaps
  std::uint64_t non_monotonic_stamp = 0;
  std::uint64_t ring_drops = 0;  ///< ring full: newest sample dropped
  std::uint64_t malformed_payload = 0;
  std::uint64_t incomplete_sample = 0;
  std::uint64_t unsupported_format = 0;
  std::uint64_t non_finite_sample = 0;  ///< NaN/Inf accel or gyro: sample dropped
  std::uint64_t other_messages = 0;     ///< valid messages of other kinds (not a fault)
  std::uint64_t clock_resets = 0;
  std::uint64_t read_errors = 0;          ///< read()/poll() errors other than EAGAIN/EINTR
  std::uint64_t hangups = 0;              ///< port hung up (device unplugged, pty master closed)
  std::uint64_t truncated_at_hangup = 0;  ///< a message was cut off by a hang-up
  std::uint64_t reopens = 0;              ///< port reopened after a hang-up
  std::uint64_t tap_sample_drops = 0;     ///< recorder's sample tap full: sample not recorded
  std::uint64_t tap_byte_drops = 0;       ///< recorder's byte tap full: a read not recorded

  [[nodiscard]] io::Json to_json_value() const;  ///< {"bytes_read": N, ...}
  [[nodiscard]] std::string to_json() const;     ///< to_json_value() on one line
  [[nodiscard]] std::string to_string() const;

  /// Copy the parser / stamper fields from live counters.
  void fill(const ParserCounters& c) noexcept;
  void fill(const StamperCounters& c) noexcept;
};

}  // namespace vigs::drivers
