#include "pty_feeder.hpp"

#include "rt/clock.hpp"

namespace vigs::drivers::test {

PacedFeeder::PacedFeeder(Pty& pty, std::vector<Segment> segments, std::function<bool()> close_when)
    : pty_(pty), segments_(std::move(segments)), close_when_(std::move(close_when)) {
  start_ns_ = rt::monotonic_ns() + rt::ms_to_ns(20);
  thread_ = std::thread([this] {
    if (segments_.empty()) return;
    const std::uint32_t stf0 = segments_.front().sample_time_fine;
    for (const Segment& s : segments_) {
      const std::uint32_t ticks = s.sample_time_fine - stf0;  // modulo 2^32
      rt::sleep_until_ns(start_ns_ + static_cast<std::int64_t>(ticks) * 100'000);
      if (!pty_.write_all(s.bytes)) return;  // the test fails on the missing bytes
      written_ += s.bytes.size();
    }
    if (!close_when_) return;
    const std::int64_t deadline = rt::monotonic_ns() + rt::s_to_ns(std::int64_t{10});
    while (!close_when_() && rt::monotonic_ns() < deadline) {
      rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(2));
    }
    pty_.close_master();
  });
}

PacedFeeder::~PacedFeeder() {
  join();
}

void PacedFeeder::join() {
  if (thread_.joinable()) thread_.join();
}

std::vector<Segment> clean_segments(const std::vector<TestSample>& samples) {
  std::vector<Segment> out;
  for (const TestSample& s : samples) out.push_back({encode(s), s.sample_time_fine});
  return out;
}

}  // namespace vigs::drivers::test
