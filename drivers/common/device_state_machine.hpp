// DeviceStateMachine: the life cycle every camera driver runs (OpenNI2, V4L2), written as a
// non-blocking state machine after PX4's drivers: each state has a timeout, a failure count forces
// a reset, and every kind of fault has its own counter.
//
//   kOpening  --open ok-->        kStreaming
//   kOpening  --open failed-->    kOpening, next attempt after a backoff (initial, doubling, max);
//                                 with reopen off (or max_open_attempts reached): kFailed
//   kStreaming --frame-->         kStreaming (failure count cleared)
//   kStreaming --no frame for frame_timeout-->             kLost (fault kFrameTimeout)
//   kStreaming --max_consecutive_errors read errors-->     kLost (fault kReadErrors: the reset)
//   kStreaming --device gone (ENODEV, disconnect)-->       kLost (fault kDeviceGone)
//   kStreaming --end of a recording-->                     kEnded
//   kLost     --device closed-->  kOpening after the first backoff; with reopen off: kFailed
//   kEnded, kFailed: final (the driver pushes its end-of-stream marker and its thread ends)
//
// The class does no I/O and reads no clock: the driver passes the monotonic time into every event
// and asks what to do (due_to_open, deadline_ns). So the whole policy is tested with a scripted
// clock (tests/drivers/test_device_state_machine.cpp). Single thread (the driver's); counters()
// may be read from any thread. No allocation.
#pragma once

#include <cstdint>
#include <string_view>

#include "rt/counters.hpp"

namespace vigs::drivers {

enum class DeviceState : std::uint8_t { kOpening, kStreaming, kLost, kEnded, kFailed };
enum class DeviceFault : std::uint8_t {
  kNone,
  kOpenFailed,    // the last open attempt failed (and no more are allowed)
  kFrameTimeout,  // no frame within frame_timeout_ns while streaming (a stalled playback, a
                  // camera that stopped sending)
  kReadErrors,    // max_consecutive_errors read errors in a row
  kDeviceGone,    // the device vanished (ENODEV, OpenNI2 disconnect)
};

[[nodiscard]] std::string_view to_string(DeviceState s) noexcept;
[[nodiscard]] std::string_view to_string(DeviceFault f) noexcept;

struct DeviceStateSettings {
  std::int64_t frame_timeout_ns = 2'000'000'000;  ///< streaming without a frame this long: lost
  std::uint32_t max_consecutive_errors = 10;      ///< read errors in a row that force a reset
  std::int64_t backoff_initial_ns = 100'000'000;  ///< first wait before reopening
  std::int64_t backoff_max_ns = 2'000'000'000;    ///< the backoff doubles up to this
  bool reopen = true;                             ///< false: the first loss or failed open is final
  std::uint32_t max_open_attempts = 0;  ///< consecutive failed opens before kFailed; 0 = no limit
};

struct DeviceStateCounters {
  std::uint64_t opens = 0;           // successful opens (the first one included)
  std::uint64_t open_failures = 0;   // failed open attempts
  std::uint64_t losses = 0;          // kStreaming -> kLost transitions (sum of the three below)
  std::uint64_t frame_timeouts = 0;  // losses by kFrameTimeout
  std::uint64_t error_resets = 0;    // losses by kReadErrors
  std::uint64_t device_gone = 0;     // losses by kDeviceGone
  std::uint64_t read_errors = 0;     // every read error, also those below the reset count
};

class DeviceStateMachine {
 public:
  explicit DeviceStateMachine(const DeviceStateSettings& settings);

  /// Back to kOpening with an attempt due at once; counters cleared (a new start()).
  void reset(std::int64_t now_ns) noexcept;

  // Events (driver thread).
  void on_open_ok(std::int64_t now_ns) noexcept;
  void on_open_failed(std::int64_t now_ns) noexcept;
  void on_frame(std::int64_t now_ns) noexcept;
  void on_read_error(std::int64_t now_ns) noexcept;
  void on_device_gone(std::int64_t now_ns) noexcept;
  void on_end_of_stream() noexcept;
  /// kLost: the driver has closed the device.
  void on_closed(std::int64_t now_ns) noexcept;
  /// kStreaming: checks the frame timeout; true when it fired (now kLost).
  bool check_timeout(std::int64_t now_ns) noexcept;

  [[nodiscard]] DeviceState state() const noexcept { return state_; }
  [[nodiscard]] DeviceFault last_fault() const noexcept { return fault_; }
  [[nodiscard]] bool final() const noexcept {
    return state_ == DeviceState::kEnded || state_ == DeviceState::kFailed;
  }
  /// kOpening: true when the next attempt is due.
  [[nodiscard]] bool due_to_open(std::int64_t now_ns) const noexcept {
    return state_ == DeviceState::kOpening && now_ns >= next_open_ns_;
  }
  /// The next time something happens without an event: the open attempt (kOpening) or the
  /// frame timeout (kStreaming).
  [[nodiscard]] std::int64_t deadline_ns() const noexcept;
  /// Current backoff (the wait before the next attempt after a failure).
  [[nodiscard]] std::int64_t backoff_ns() const noexcept { return backoff_ns_; }
  [[nodiscard]] DeviceStateCounters counters() const noexcept;
  [[nodiscard]] const DeviceStateSettings& settings() const noexcept { return settings_; }

 private:
  void lose(DeviceFault why, std::int64_t now_ns) noexcept;

  DeviceStateSettings settings_;
  DeviceState state_ = DeviceState::kOpening;
  DeviceFault fault_ = DeviceFault::kNone;
  std::int64_t next_open_ns_ = 0;
  std::int64_t last_frame_ns_ = 0;
  std::int64_t backoff_ns_ = 0;
  std::uint32_t consecutive_errors_ = 0;
  std::uint32_t consecutive_open_failures_ = 0;
  rt::SingleWriterCounter opens_, open_failures_, losses_, frame_timeouts_, error_resets_,
      device_gone_, read_errors_;
};

}  // namespace vigs::drivers
