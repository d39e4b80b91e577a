#include "drivers/gpio_trigger/gpio_trigger.hpp"

#include <gpiod.h>
#include <poll.h>

#include <cerrno>
#include <cstring>

#include "core/config/camera_settings.hpp"
#include "core/config/rt_settings.hpp"
#include "rt/clock.hpp"
#include "rt/queue_policy.hpp"
#include "rt/thread_table.hpp"

namespace vigs::drivers {

GpioTriggerSettings gpio_trigger_settings(const config::CameraSettings& camera,
                                          const config::RtSettings& rt) {
  GpioTriggerSettings s;
  s.chip = camera.trigger_chip;
  s.line = static_cast<unsigned>(camera.trigger_line);
  s.realtime_thread = rt.realtime_priorities;
  s.pin_cpu = rt.pin_cpus;
  return s;
}

GpioTrigger::GpioTrigger(const GpioTriggerSettings& settings, rt::SpscRing<TriggerEdge>& out)
    : settings_(settings), out_(out) {
  if (settings.wait_timeout_ms <= 0) {
    throw std::invalid_argument("GpioTrigger: wait_timeout_ms must be > 0");
  }
}

GpioTrigger::~GpioTrigger() {
  stop();
}

void GpioTrigger::start() {
  if (thread_) return;
  const std::string what =
      "GPIO line " + std::to_string(settings_.line) + " of '" + settings_.chip + "'";
  chip_ = gpiod_chip_open_lookup(settings_.chip.c_str());
  if (chip_ == nullptr)
    throw GpioTriggerError(what + ": cannot open the chip: " + std::strerror(errno));
  line_ = gpiod_chip_get_line(chip_, settings_.line);
  if (line_ == nullptr) {
    const int e = errno;
    release_line();
    throw GpioTriggerError(what + ": no such line: " + std::strerror(e));
  }
  if (gpiod_line_request_rising_edge_events(line_, "vigs") != 0) {
    const int e = errno;
    release_line();
    throw GpioTriggerError(what + ": cannot request rising-edge events: " + std::strerror(e));
  }
  fd_ = gpiod_line_event_get_fd(line_);
  if (fd_ < 0) {
    const int e = errno;
    release_line();
    throw GpioTriggerError(what + ": no event fd: " + std::strerror(e));
  }
  launch();
}

void GpioTrigger::start_with_event_fd(int fd) {
  if (thread_) return;
  fd_ = fd;
  launch();
}

void GpioTrigger::launch() {
  for (rt::SingleWriterCounter* c :
       {&rising_, &falling_, &pushed_, &dropped_, &tap_dropped_, &read_errors_, &non_monotonic_}) {
    c->reset();
  }
  source_closed_.store(false, std::memory_order_relaxed);
  last_t_ns_ = 0;
  rt::ThreadSpec spec = rt::thread_spec("gpio_trigger");
  if (!settings_.realtime_thread) spec.sched_fifo_priority = 0;
  if (!settings_.pin_cpu) spec.cpu = -1;
  thread_.emplace(spec, [this](std::stop_token stop) { run(stop); });
}

void GpioTrigger::stop() {
  if (thread_) {
    thread_->request_stop();
    thread_->join();
    thread_.reset();
  }
  release_line();
}

void GpioTrigger::release_line() noexcept {
  if (line_ != nullptr) gpiod_line_release(line_);
  line_ = nullptr;
  if (chip_ != nullptr) gpiod_chip_close(chip_);
  chip_ = nullptr;
  fd_ = -1;
}

void GpioTrigger::run(const std::stop_token& stop) noexcept {
  constexpr unsigned kBurst = 16;
  gpiod_line_event events[kBurst];
  while (!stop.stop_requested()) {
    pollfd p{fd_, POLLIN | POLLPRI, 0};
    const int n = ::poll(&p, 1, settings_.wait_timeout_ms);
    if (n <= 0) continue;                         // timeout (no edge) or EINTR
    if ((p.revents & (POLLIN | POLLPRI)) == 0) {  // POLLHUP / POLLERR without data: gone
      source_closed_.store(true, std::memory_order_release);
      return;
    }
    // libgpiod decodes the kernel's struct gpioevent_data (16 bytes each) itself.
    const int got = gpiod_line_event_read_fd_multiple(fd_, events, kBurst);
    if (got < 0) {
      read_errors_.add();
      if (errno != EAGAIN && errno != EIO) {
        rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(settings_.wait_timeout_ms));
      }
      continue;
    }
    if (got == 0) {  // end of file: the writer (or the line) went away
      source_closed_.store(true, std::memory_order_release);
      return;
    }
    for (int i = 0; i < got; ++i) {
      if (events[i].event_type != GPIOD_LINE_EVENT_RISING_EDGE) {
        falling_.add();
        continue;
      }
      const std::int64_t t_ns = rt::from_timespec(events[i].ts);
      if (t_ns <= last_t_ns_) {
        non_monotonic_.add();
        continue;
      }
      last_t_ns_ = t_ns;
      const TriggerEdge edge{t_ns, rising_.get()};
      rising_.add();
      if (rt::push_or_drop(out_, edge, dropped_)) pushed_.add();
      if (tap_ != nullptr) (void)rt::push_or_drop(*tap_, edge, tap_dropped_);
    }
  }
}

GpioTriggerCounters GpioTrigger::counters() const noexcept {
  GpioTriggerCounters c;
  c.source_closed = source_closed_.load(std::memory_order_acquire);
  c.rising = rising_.get();
  c.falling = falling_.get();
  c.pushed = pushed_.get();
  c.dropped_ring_full = dropped_.get();
  c.tap_dropped = tap_dropped_.get();
  c.read_errors = read_errors_.get();
  c.non_monotonic = non_monotonic_.get();
  return c;
}

io::Json to_json_value(const GpioTriggerCounters& c) {
  return {{"rising", c.rising},
          {"falling", c.falling},
          {"pushed", c.pushed},
          {"dropped_ring_full", c.dropped_ring_full},
          {"tap_dropped", c.tap_dropped},
          {"read_errors", c.read_errors},
          {"non_monotonic", c.non_monotonic},
          {"source_closed", c.source_closed}};
}

}  // namespace vigs::drivers
