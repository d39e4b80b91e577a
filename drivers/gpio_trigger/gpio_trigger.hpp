// GpioTrigger: the `gpio_trigger` thread of the thread table. It takes the rising edges of a
// camera's frame-sync (strobe) line from the kernel through libgpiod 1.6, each with the kernel's
// event stamp, and pushes them as TriggerEdges into the camera driver's ring (and, when set, the
// recorder's tap ring).
//
// Source: a line (`chip` as gpiod_chip_open_lookup takes it -- "gpiochip0", "/dev/gpiochip0",
// a label or a number -- and `line` offset), requested for rising-edge events with consumer
// "vigs"; or, for tests, any fd that delivers the kernel's `struct gpioevent_data` records
// (open_event_fd): libgpiod's own gpiod_line_event_read_fd_multiple decodes both. This kernel has
// no gpiochip, so the tests write kernel-format records into a pipe.
// Stamps: the GPIO uAPI v1 stamps events with CLOCK_MONOTONIC since Linux 5.7 (CLOCK_REALTIME
// before: use a 5.7+ kernel, as Debian 12's 6.1). libgpiod returns them as a timespec; the edge's
// t_ns is that, unchanged.
// Loop: poll(fd, wait_timeout_ms) (the bound on stop()), read up to 16 events at once; rising
// edges are pushed (push_or_drop: a full ring drops the newest edge and counts it, per ring);
// falling edges (a line requested for both) are counted and ignored; a failed or short read is a
// read error; end of file / POLLHUP ends the source (source_closed) and the thread.
// Real-time: after start() no allocation, lock or log.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "drivers/common/trigger_edge.hpp"
#include "io/json_text.hpp"
#include "rt/counters.hpp"
#include "rt/rt_thread.hpp"
#include "rt/spsc_ring.hpp"

struct gpiod_chip;
struct gpiod_line;

namespace vigs::config {
struct CameraSettings;
struct RtSettings;
}  // namespace vigs::config

namespace vigs::drivers {

class GpioTriggerError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct GpioTriggerSettings {
  std::string chip;   ///< gpiod_chip_open_lookup name; empty with open_event_fd
  unsigned line = 0;  ///< line offset on the chip
  int wait_timeout_ms = 20;
  bool realtime_thread = true;
  bool pin_cpu = true;
};

/// From the robot config: camera.trigger_chip, camera.trigger_line, rt.realtime_priorities,
/// rt.pin_cpus.
[[nodiscard]] GpioTriggerSettings gpio_trigger_settings(const config::CameraSettings& camera,
                                                        const config::RtSettings& rt);

struct GpioTriggerCounters {
  std::uint64_t rising = 0;   // rising edges read
  std::uint64_t falling = 0;  // falling edges read (ignored)
  std::uint64_t pushed = 0;   // edges queued to the driver's ring
  std::uint64_t dropped_ring_full = 0;
  std::uint64_t tap_dropped = 0;    // the recorder tap was full
  std::uint64_t read_errors = 0;    // failed or short event reads
  std::uint64_t non_monotonic = 0;  // an edge stamped before the previous one (dropped)
  bool source_closed = false;       // the event fd reached end of file
};

/// {"rising": N, ..., "source_closed": bool}: every counter by its name (stats.json).
[[nodiscard]] io::Json to_json_value(const GpioTriggerCounters& c);

class GpioTrigger {
 public:
  GpioTrigger(const GpioTriggerSettings& settings, rt::SpscRing<TriggerEdge>& out);
  ~GpioTrigger();
  GpioTrigger(const GpioTrigger&) = delete;
  GpioTrigger& operator=(const GpioTrigger&) = delete;

  /// A second ring (the recorder's); set before start(). Full: drop and count, never wait.
  void set_tap(rt::SpscRing<TriggerEdge>* tap) noexcept { tap_ = tap; }
  /// Requests `chip`/`line` for rising-edge events and starts the thread. Throws GpioTriggerError
  /// naming the chip and line.
  void start();
  /// Tests: reads kernel-format gpioevent_data records from `fd` (not owned) instead of a line.
  void start_with_event_fd(int fd);
  void stop();
  [[nodiscard]] bool running() const noexcept { return thread_.has_value(); }
  [[nodiscard]] GpioTriggerCounters counters() const noexcept;
  /// "chip:line": the edges' source as recordings name it (TimeReference.source).
  [[nodiscard]] std::string source() const {
    return settings_.chip + ":" + std::to_string(settings_.line);
  }

 private:
  void launch();
  void run(const std::stop_token& stop) noexcept;
  void release_line() noexcept;

  GpioTriggerSettings settings_;
  rt::SpscRing<TriggerEdge>& out_;
  rt::SpscRing<TriggerEdge>* tap_ = nullptr;
  gpiod_chip* chip_ = nullptr;
  gpiod_line* line_ = nullptr;
  int fd_ = -1;
  std::int64_t last_t_ns_ = 0;
  rt::SingleWriterCounter rising_, falling_, pushed_, dropped_, tap_dropped_, read_errors_,
      non_monotonic_;
  std::atomic<bool> source_closed_{false};
  std::optional<rt::RtThread> thread_;
};

}  // namespace vigs::drivers
