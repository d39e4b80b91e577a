// Test helper: a pseudo-terminal whose master is written by a feeder thread, paced by each
// segment's device time (a pty does not pace by baud), while the code under test reads the slave.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "drivers/serial_imu/pseudo_terminal.hpp"
#include "xsens_test_stream.hpp"

namespace vigs::drivers::test {

/// The pty pair now lives in drivers/serial_imu/pseudo_terminal.hpp (vigs run uses it too).
using Pty = drivers::PseudoTerminal;

/// Writes segments to the master: segment k at start + (stf_k - stf_0) * 100 us. With
/// `close_when`, closes the master after the last write once close_when() is true (polled for up
/// to 10 s): a stream cut off and then the device unplugged. Closing a pty master discards what
/// the slave has not read yet, so the test waits until the reader has everything.
class PacedFeeder {
 public:
  PacedFeeder(Pty& pty, std::vector<Segment> segments, std::function<bool()> close_when = {});
  ~PacedFeeder();  // joins
  void join();
  [[nodiscard]] std::int64_t start_ns() const { return start_ns_; }
  [[nodiscard]] std::size_t bytes_written() const { return written_.load(); }

 private:
  Pty& pty_;
  std::vector<Segment> segments_;
  std::function<bool()> close_when_;
  std::int64_t start_ns_ = 0;
  std::atomic<std::size_t> written_{0};
  std::thread thread_;
};

/// Segments of clean messages for `samples`.
std::vector<Segment> clean_segments(const std::vector<TestSample>& samples);

}  // namespace vigs::drivers::test
