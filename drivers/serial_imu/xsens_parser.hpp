// XsensMtParser: resynchronising parser of Xsens MT binary (Xbus) messages; MTData2 (MID 0x36)
// with SampleTimeFine, Acceleration and RateOfTurn becomes one DeviceImuSample.
//
// Resynchronisation: a candidate starts at a preamble byte 0xFA. It is rejected as soon as a
// byte proves it wrong (bus id not 0xFF, length above xsens::kMaxDataSize, checksum failure);
// then only its preamble is dropped and the search restarts at the very next byte, so a good
// message that began inside a truncated or corrupted one is still found. Length fields are never
// trusted beyond the maximum, so a corrupted length costs at most one maximum-size message of
// look-ahead. Each accepted message has exactly one outcome: packets_ok, other_messages,
// malformed_payload, incomplete_sample or unsupported_format.
//
// Data IDs: float32 (0x..0), fixed 12.20 (0x..1) and float64 (0x..3) precisions are decoded;
// fixed 16.32 is counted as unsupported_format. The coordinate-system bits select the earth
// reference frame (ENU/NED/NWU); Acceleration and RateOfTurn are sensor-frame vectors, so they are
// read the same under every setting. Unknown data IDs are skipped.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "drivers/serial_imu/imu_protocol_parser.hpp"
#include "drivers/serial_imu/xsens_mt.hpp"

namespace vigs::drivers {

class XsensMtParser final : public ImuProtocolParser {
 public:
  void feed(const std::uint8_t* data, std::size_t size, ImuSampleSink& sink) noexcept override;
  void reset() noexcept override { held_ = 0; }
  [[nodiscard]] std::size_t pending_bytes() const noexcept override { return held_; }
  [[nodiscard]] DeviceClockSpec clock() const noexcept override {
    return {xsens::kSampleTimeFineHz, 32};
  }
  [[nodiscard]] std::string_view protocol_name() const noexcept override { return "xsens_mt"; }
  [[nodiscard]] const ParserCounters& counters() const noexcept override { return counters_; }

 private:
  enum class Verdict : std::uint8_t { kNeedMore, kAccept, kReject };
  struct Check {
    Verdict verdict;
    std::size_t size;  // kNeedMore: total bytes needed to decide; kAccept: message size
  };

  // Examines a candidate starting with the preamble; counts bad_checksum / oversize_length when
  // it rejects.
  Check check(const std::uint8_t* p, std::size_t avail) noexcept;
  void accept(const std::uint8_t* msg, std::size_t size, ImuSampleSink& sink) noexcept;
  void drop_held_front(std::size_t count) noexcept;

  std::array<std::uint8_t, xsens::kMaxMessageSize> held_buf_{};
  std::size_t held_ = 0;  // bytes of an undecided candidate; held_buf_[0] is a preamble
  ParserCounters counters_;
};

}  // namespace vigs::drivers
