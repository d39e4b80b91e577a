#include "drivers/serial_imu/serial_imu_driver.hpp"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>

#include "core/config/imu_settings.hpp"
#include "core/config/rt_settings.hpp"
#include "drivers/serial_imu/parser_factory.hpp"
#include "rt/clock.hpp"
#include "rt/queue_policy.hpp"
#include "rt/thread_table.hpp"

namespace vigs::drivers {

SerialImuDriverSettings serial_imu_settings(const config::ImuSettings& imu,
                                            const config::RtSettings& rt) {
  SerialImuDriverSettings s;
  s.port = imu.port;
  s.baud = imu.baud;
  s.protocol = imu.protocol;
  s.realtime_thread = rt.realtime_priorities;
  s.pin_cpu = rt.pin_cpus;
  s.stamper.nominal_rate_hz = imu.rate_hz;
  return s;
}

void SerialImuDriver::RingOutput::on_stamped(const ImuSample& sample) noexcept {
  (void)rt::push_or_drop(ring_, sample, drops);
  if (tap != nullptr) (void)rt::push_or_drop(*tap, sample, tap_drops);
}

SerialImuDriver::SerialImuDriver(const SerialImuDriverSettings& settings,
                                 rt::SpscRing<ImuSample>& out)
    : settings_(settings),
      output_(out),
      parser_(make_imu_parser(settings.protocol)),
      stamper_(parser_->clock(), settings.stamper, output_) {}

SerialImuDriver::~SerialImuDriver() {
  stop();
}

void SerialImuDriver::start() {
  if (thread_) return;
  port_ = SerialPort::open(settings_.port, settings_.baud);
  parser_->reset();
  stamper_.reset();
  rt::ThreadSpec spec = rt::thread_spec("imu_driver");
  if (!settings_.realtime_thread) spec.sched_fifo_priority = 0;
  if (!settings_.pin_cpu) spec.cpu = -1;
  thread_.emplace(spec, [this](std::stop_token stop) { run(stop); });
}

void SerialImuDriver::stop() {
  if (!thread_) return;
  thread_->request_stop();
  thread_->join();
  thread_.reset();
  port_.close();
}

void SerialImuDriver::run(const std::stop_token& stop) noexcept {
  const std::int64_t poll_period_ns = rt::ms_to_ns(settings_.poll_timeout_ms);
  // A /dev/pts/N port is never reopened: pty numbers are reused at once by unrelated terminals
  // and replay feeders, so the name would soon lead to someone else's stream.
  const bool is_pty = port_.path().rfind("/dev/pts/", 0) == 0;
  const std::int64_t reopen_period_ns = is_pty ? 0 : rt::ms_to_ns(settings_.reopen_interval_ms);
  int fd = port_.fd();
  bool hung_up = false;
  std::int64_t next_reopen_ns = 0;
  while (!stop.stop_requested()) {
    if (fd < 0) {
      // Port lost: try to open the same path again at the reopen interval (a re-plugged USB
      // adapter comes back under its udev name). The new connection gets a new time base.
      const std::int64_t now = rt::monotonic_ns();
      if (now < next_reopen_ns) {
        rt::sleep_until_ns(std::min(next_reopen_ns, now + poll_period_ns));
        continue;
      }
      next_reopen_ns = now + reopen_period_ns;
      if (port_.reopen()) {
        fd = port_.fd();
        reopens_.add();
        parser_->reset();
        stamper_.reset();
      }
      continue;
    }

    pollfd pfd{fd, POLLIN, 0};
    const int ready = ::poll(&pfd, 1, settings_.poll_timeout_ms);
    if (ready < 0) {
      if (errno != EINTR) {
        read_errors_.add();
        rt::sleep_until_ns(rt::monotonic_ns() + poll_period_ns);
      }
      continue;
    }
    if (ready == 0) continue;

    bool got_data = false;
    bool eof = false;
    if ((pfd.revents & POLLIN) != 0) {
      const ssize_t n = ::read(fd, read_buf_.data(), read_buf_.size());
      if (n > 0) {
        const std::int64_t host_ns = rt::monotonic_ns();
        got_data = true;
        hung_up = false;
        bytes_read_.add(static_cast<std::uint64_t>(n));
        if (bytes_tap_ != nullptr) tap_bytes(host_ns, static_cast<std::size_t>(n));
        stamper_.begin_read(host_ns);
        parser_->feed(read_buf_.data(), static_cast<std::size_t>(n), stamper_);
        stamper_.end_read();
      } else if (n == 0 || errno == EIO) {
        eof = true;
      } else if (errno != EAGAIN && errno != EINTR) {
        read_errors_.add();
      }
    }
    if (!got_data && (eof || (pfd.revents & (POLLHUP | POLLERR | POLLNVAL)) != 0)) {
      // Readable or hung up but nothing read: the other end is gone (EIO / EOF on a pty slave
      // whose master closed, or an unplugged USB adapter). Count the episode once, flush, and
      // never spin: close and retry later, or (reopen disabled) sleep a poll period.
      if (!hung_up) {
        hung_up = true;
        if (parser_->pending_bytes() > 0) {
          truncated_at_hangup_.add();
          parser_->reset();
        }
        stamper_.release();
        hangups_.add();  // last: a reader that sees the hang-up sees its consequences too
      }
      if (reopen_period_ns > 0) {
        port_.close();
        fd = -1;
        next_reopen_ns = rt::monotonic_ns() + reopen_period_ns;
      } else {
        rt::sleep_until_ns(rt::monotonic_ns() + poll_period_ns);
      }
    }
  }
  stamper_.release();
}

void SerialImuDriver::tap_bytes(std::int64_t t_ns, std::size_t n) noexcept {
  for (std::size_t off = 0; off < n; off += SerialBytes::kCapacity) {
    // Built in place in the ring's slot: no 512-byte copy through the stack.
    if (!bytes_tap_->try_emplace(t_ns, read_buf_.data() + off, n - off)) tap_byte_drops_.add();
  }
}

SerialImuFaults SerialImuDriver::faults() const noexcept {
  SerialImuFaults f;
  f.fill(parser_->counters());
  f.fill(stamper_.counters());
  f.bytes_read = bytes_read_.get();
  f.ring_drops = output_.drops.get();
  f.read_errors = read_errors_.get();
  f.hangups = hangups_.get();
  f.truncated_at_hangup = truncated_at_hangup_.get();
  f.reopens = reopens_.get();
  f.tap_sample_drops = output_.tap_drops.get();
  f.tap_byte_drops = tap_byte_drops_.get();
  return f;
}

const rt::ThreadApplyStatus* SerialImuDriver::thread_status() const noexcept {
  return thread_ ? &thread_->status() : nullptr;
}

}  // namespace vigs::drivers
