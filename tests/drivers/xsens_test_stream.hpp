// Test helper: Xsens MTData2 byte streams built from real IMU samples (EuRoC V1_02 imu0.csv,
// encoded as the device would send them) with faults injected at known places, and the exact
// counters and surviving samples a correct parser must report for them.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "drivers/serial_imu/xsens_mt.hpp"

namespace vigs::drivers::test {

struct TestSample {
  std::uint32_t sample_time_fine = 0;  ///< 10 kHz ticks
  std::array<double, 3> accel_mps2{};  ///< float32-exact values
  std::array<double, 3> gyro_rps{};
};

/// `count` consecutive EuRoC samples as float32-exact values, SampleTimeFine starting at `stf0`
/// and stepping by `ticks_per_sample` (wrapping modulo 2^32). Values are nudged by a few ulps
/// where needed so that no encoded message contains the byte pair FA FF after its start (a false
/// header would make fault counts depend on the data, not on the injected faults).
std::vector<TestSample> euroc_samples(std::size_t count, std::uint32_t stf0,
                                      std::uint32_t ticks_per_sample = 50);

std::vector<std::uint8_t> encode(const TestSample& s);

/// What a correct parser + stamper must report for a built stream.
struct ExpectedCounts {
  std::uint64_t packets_ok = 0;
  std::uint64_t bad_checksum = 0;
  std::uint64_t resync_bytes_skipped = 0;
  std::uint64_t oversize_length = 0;
  std::uint64_t bytes_in_messages = 0;
  std::uint64_t sample_counter_gap = 0;
  std::uint64_t samples_missed = 0;
  std::size_t pending_at_end = 0;  ///< bytes of a cut-off message at the end
};

/// One piece of the stream with the device time it belongs to (for paced feeding).
struct Segment {
  std::vector<std::uint8_t> bytes;
  std::uint32_t sample_time_fine = 0;
};

class FaultyStreamBuilder {
 public:
  explicit FaultyStreamBuilder(std::uint32_t seed) : rng_(seed) {}

  void good(const TestSample& s);
  /// `n` random bytes, none of them a preamble.
  void garbage(std::size_t n, std::uint32_t stf);
  /// The message with one bit flipped after its length byte: fails its checksum.
  void flipped(const TestSample& s);
  /// Only the first `keep` (>= 4) bytes of the message.
  void truncated(const TestSample& s, std::size_t keep);
  /// A header announcing an extended length above the maximum (FA FF 36 FF 7F FF).
  void oversize_header(std::uint32_t stf);
  /// Cut the stream: the first `keep` bytes of a last message, then nothing.
  void cut_off(const TestSample& s, std::size_t keep);

  /// Makes sure no truncated message's span has a valid checksum by chance (changing the
  /// fragment's last byte where needed) and that no false header exists, then returns the
  /// counts. Throws std::logic_error if the stream cannot be a valid test.
  ExpectedCounts finish();

  [[nodiscard]] const std::vector<Segment>& segments() const { return segments_; }
  [[nodiscard]] std::vector<std::uint8_t> bytes() const;
  /// The samples a correct parser must deliver, in order.
  [[nodiscard]] const std::vector<TestSample>& survivors() const { return survivors_; }

 private:
  void lost(std::size_t n) { lost_run_ += n; }
  void push(std::vector<std::uint8_t> bytes, std::uint32_t stf);

  std::mt19937 rng_;
  std::vector<Segment> segments_;
  std::vector<TestSample> survivors_;
  std::vector<std::size_t> truncated_segments_;  // indices of truncated messages
  std::size_t size_ = 0;
  std::size_t lost_run_ = 0;
  bool cut_ = false;
  ExpectedCounts counts_;
};

}  // namespace vigs::drivers::test
