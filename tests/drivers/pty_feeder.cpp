#include "pty_feeder.hpp"

#include <fcntl.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>
#include <system_error>

#include "rt/clock.hpp"

namespace vigs::drivers::test {

Pty::Pty() {
  master_ = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master_ < 0 || ::grantpt(master_) != 0 || ::unlockpt(master_) != 0) {
    throw std::system_error(errno, std::generic_category(), "posix_openpt/grantpt/unlockpt");
  }
  const char* name = ::ptsname(master_);
  if (name == nullptr) throw std::system_error(errno, std::generic_category(), "ptsname");
  slave_path_ = name;
  slave_ = ::open(name, O_RDWR | O_NOCTTY);
  if (slave_ < 0) throw std::system_error(errno, std::generic_category(), "open " + slave_path_);
  termios tio{};
  ::tcgetattr(slave_, &tio);
  ::cfmakeraw(&tio);
  if (::tcsetattr(slave_, TCSANOW, &tio) != 0) {
    throw std::system_error(errno, std::generic_category(), "tcsetattr " + slave_path_);
  }
}

Pty::~Pty() {
  close_master();
  if (slave_ >= 0) ::close(slave_);
}

void Pty::close_master() {
  if (master_ >= 0) ::close(master_);
  master_ = -1;
}

PacedFeeder::PacedFeeder(Pty& pty, std::vector<Segment> segments, std::function<bool()> close_when)
    : pty_(pty), segments_(std::move(segments)), close_when_(std::move(close_when)) {
  start_ns_ = rt::monotonic_ns() + rt::ms_to_ns(20);
  thread_ = std::thread([this] {
    if (segments_.empty()) return;
    const std::uint32_t stf0 = segments_.front().sample_time_fine;
    for (const Segment& s : segments_) {
      const std::uint32_t ticks = s.sample_time_fine - stf0;  // modulo 2^32
      rt::sleep_until_ns(start_ns_ + static_cast<std::int64_t>(ticks) * 100'000);
      std::size_t done = 0;
      while (done < s.bytes.size()) {
        const ssize_t n = ::write(pty_.master_fd(), s.bytes.data() + done, s.bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return;  // the test fails on the missing bytes
        done += static_cast<std::size_t>(n);
      }
      written_ += done;
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
