// Openni2Driver: reads an OpenNI2 RGB-D device (a live sensor, or a `.oni` clip played back by
// real OpenNI2) on its own real-time thread, pairs depth with colour, copies each pair into a
// FramePool slot and pushes its FrameHandle into an rt ring.
//
// Thread: rt thread table entry `rgbd_driver`, created by start(), joined by stop(). Loop:
// OpenNI::waitForAnyStream(depth, colour) with a timeout (wait_timeout_ms, so stop() returns
// within about that), readFrame the ready stream, check its size, pair by device timestamp
// (FramePairer), then acquire a pool slot, copy depth (16-bit mm) and RGB8, stamp (DeviceClock:
// device time -> CLOCK_MONOTONIC) and push. The thread is a PinnedStackThread rather than
// rt::RtThread (same ThreadSpec, same stop token): its stack is never unmapped, which keeps
// OpenNI2 2.2 from crashing (pinned_stack_thread.hpp).
//
// Ring policy: push_or_drop: when the ring is full the newest frame is dropped, its slot goes back
// to the pool at once, and it is counted (dropped_ring_full). An empty pool drops the pair
// (dropped_pool_empty). The driver never waits for the consumer.
//
// States (DeviceStateMachine, drivers/common/device_state_machine.hpp): opening, streaming, lost,
// reopening after a backoff (100 ms doubling to 2 s), ended, failed. start() opens the device
// itself and throws on failure (unless wait_for_device); afterwards everything happens on the
// driver thread: a stream without a frame for frame_timeout_ms, or max_consecutive_errors
// failed waits/reads in a row (the failure count that forces a reset), is lost: the driver
// closes the device and reopens it by URI with the backoff, re-anchoring the clock. A live
// sensor is reopened (reopen_live); a .oni clip is not (reopen_files): its frame timeout is the
// playback watchdog -- a truncated clip on which OpenNI2's player spins at end of file ends the
// stream as failed, with fault_message() naming the file and the frames played, instead of
// hanging. Reopening runs OpenNI2's open path on the driver thread (it allocates); that is a
// recovery path, not the per-frame one.
//
// Playback: Device::open(path) in OpenNI2's manual mode (setSpeed(-1): the player delivers the
// next recorded frame when a read finds none, never skipping). playback_speed -1 (the default) is
// lockstep: every frame as fast as the reader takes them. playback_speed > 0 is real time (`vigs
// run --through-drivers`): the driver holds each pair until its recorded time comes on the host
// clock (PlaybackPacer, drivers/common/playback_pacer.hpp), as a sensor delivers it. OpenNI2's
// own real-time pacing (setSpeed(1)) is not used: it drifts about 1 % fast (see that header).
// Repeat left on (see the .cpp), no seek. After the clip's last
// frame (or a final fault) the driver sets end_of_stream(), pushes an invalid FrameHandle as the
// end-of-stream marker (retrying every millisecond until the consumer makes room, or stop()) and
// its thread ends.
//
// Real-time: all buffers are the pool's; the loop itself does not allocate, lock or log.
// OpenNI2's own calls on that path (waitForAnyStream, readFrame, frame reference release) take
// OpenNI2's internal critical sections, and OpenNI2 2.2 allocates about one operator new per
// frame in frame release (tests/drivers/test_openni2_alloc.cpp); that is outside this code.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "drivers/common/device_state_machine.hpp"
#include "drivers/common/frame_pairer.hpp"
#include "drivers/common/frame_tap.hpp"
#include "drivers/common/playback_pacer.hpp"
#include "drivers/common/rgbd_driver_counters.hpp"
#include "drivers/common/trigger_matcher.hpp"
#include "drivers/openni2/device_clock.hpp"
#include "drivers/openni2/pinned_stack_thread.hpp"
#include "rt/counters.hpp"
#include "rt/frame_pool.hpp"
#include "rt/spsc_ring.hpp"
#include "rt/thread_table.hpp"

namespace vigs::config {
struct CameraSettings;
struct RtSettings;
}  // namespace vigs::config

namespace vigs::drivers {

// Opening or configuring the device failed; the message names the URI (or file) and the step.
class Openni2Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Openni2DriverSettings {
  std::string uri;                ///< OpenNI2 device URI or .oni file; empty = first device
  std::uint32_t width_px = 640;   ///< camera image size both streams must have
  std::uint32_t height_px = 480;  ///< px
  double rate_hz = 30.0;          ///< frame rate: live video mode, pairing tolerance (T/2)
  int wait_timeout_ms = 20;       ///< bound on stop() latency
  bool register_depth = true;     ///< depth-to-colour registration where the device has it
  bool realtime_thread = true;    ///< request the thread table's SCHED_FIFO priority
  bool pin_cpu = true;            ///< pin to the thread table's CPU
  // Life cycle (DeviceStateMachine).
  int frame_timeout_ms = 2000;          ///< streaming without a frame this long: lost (playback:
                                        ///< the progress watchdog)
  int max_consecutive_errors = 10;      ///< failed waits/reads in a row that force a reset
  int reopen_backoff_initial_ms = 100;  ///< first wait before reopening a lost device
  int reopen_backoff_max_ms = 2000;     ///< the wait doubles up to this
  bool reopen_live = true;       ///< reopen a lost live sensor (false: the loss ends the stream)
  bool reopen_files = false;     ///< reopen a .oni path whose playback stalled (tests, re-recorded
                                 ///< clips); false: a stalled clip ends the stream as failed
  bool wait_for_device = false;  ///< start() does not open: the thread keeps trying (backoff)
  double playback_speed = -1.0;  ///< .oni: -1 = lockstep (every frame), 1 = real time, 2 = 2x
  int max_hold_ms = 1000;        ///< real-time playback: a longer gap in a clip re-anchors
};

/// Driver settings from the robot config (camera.device, camera.width_px, camera.height_px,
/// camera.rate_hz, rt.realtime_priorities, rt.pin_cpus).
[[nodiscard]] Openni2DriverSettings openni2_settings(const config::CameraSettings& camera,
                                                     const config::RtSettings& rt);

class Openni2Driver {
 public:
  /// `pool` must hold width_px x height_px frames with 3 colour channels (rgb8), else
  /// std::invalid_argument. Both references must outlive the driver.
  Openni2Driver(const Openni2DriverSettings& settings, rt::FramePool& pool,
                rt::SpscRing<rt::FrameHandle>& out);
  ~Openni2Driver();
  Openni2Driver(const Openni2Driver&) = delete;
  Openni2Driver& operator=(const Openni2Driver&) = delete;

  /// Opens the device and starts both streams and the read thread. Throws Openni2Error naming
  /// the URI: missing or unreadable file, no device, no depth or colour stream, a stream whose
  /// size (both sizes named) or pixel format differs from the settings. Nothing is left open
  /// after a throw.
  void start();
  /// Frame sync: each pair's stamp becomes its GPIO edge's (TriggerMatcher; set before start(),
  /// used on the driver thread only).
  void set_trigger(TriggerMatcher* matcher) noexcept { trigger_ = matcher; }
  /// The recorder's tap (drivers/common/frame_tap.hpp); set before start().
  void set_tap(rt::SpscRing<rt::FrameHandle>* tap) noexcept { tap_.set(tap); }
  /// Stops and joins the read thread, then closes the streams and the device. Idempotent.
  void stop();
  [[nodiscard]] bool running() const noexcept { return thread_.has_value(); }

  /// True once the stream has ended: playback read the clip's last frame, or a final fault
  /// (fault() != kNone; a lost live sensor only with reopen_live off). Never otherwise.
  [[nodiscard]] bool end_of_stream() const noexcept {
    return end_of_stream_.load(std::memory_order_acquire);
  }
  /// True when the opened device is a file (playback).
  [[nodiscard]] bool is_file() const noexcept { return is_file_.load(std::memory_order_relaxed); }
  /// True when depth-to-colour registration was switched on.
  [[nodiscard]] bool registered() const noexcept {
    return registered_.load(std::memory_order_relaxed);
  }
  /// Current life-cycle state (any thread).
  [[nodiscard]] DeviceState state() const noexcept {
    return state_.load(std::memory_order_acquire);
  }
  /// Why the stream ended, once end_of_stream(): kNone for a clip played to its end.
  [[nodiscard]] DeviceFault fault() const noexcept;
  /// Once end_of_stream() with a fault: what failed, naming the URI (empty otherwise).
  [[nodiscard]] std::string fault_message() const;

  /// Host CLOCK_MONOTONIC minus device time (ns) of the current clock anchor (DeviceClock): a
  /// frame of device time d is stamped d + this. Empty before the first frame; a reopen or a
  /// device clock going back re-anchors it. Any thread.
  [[nodiscard]] std::optional<std::int64_t> host_minus_device_ns() const noexcept {
    const std::int64_t v = host_minus_device_ns_.load(std::memory_order_acquire);
    return v == kNoAnchor ? std::nullopt : std::optional<std::int64_t>(v);
  }

  /// Counter snapshot; callable from any thread at any time.
  [[nodiscard]] RgbdDriverCounters counters() const noexcept;
  /// What the OS granted the read thread (valid while running).
  [[nodiscard]] const rt::ThreadApplyStatus* thread_status() const noexcept;

 private:
  struct Device;  // the OpenNI2 objects (kept out of this header)

  void open_device();  // throws Openni2Error; nothing is left open after a throw
  void run(const std::stop_token& stop) noexcept;
  void stream_step() noexcept;
  void try_reopen() noexcept;
  void lose_device() noexcept;
  void set_fault_text(const char* text) noexcept;
  // Returns false when the frame was not read (error) or not part of this run (clip restart).
  bool read_one(int stream_index) noexcept;
  void emit_pair() noexcept;
  // Real-time playback: sleeps until the pair of device time t_device_ns is due (or stop).
  void hold_until_due(std::int64_t t_device_ns) noexcept;
  void finish_stream(const std::stop_token& stop) noexcept;
  void close_device() noexcept;

  Openni2DriverSettings settings_;
  rt::FramePool& pool_;
  rt::SpscRing<rt::FrameHandle>& out_;
  std::unique_ptr<Device> device_;
  FramePairer pairer_;
  DeviceClock clock_;
  PlaybackPacer pacer_;
  bool paced_ = false;                     // this open is a clip played in real time
  const std::stop_token* stop_ = nullptr;  // the read thread's, while it runs
  TriggerMatcher* trigger_ = nullptr;
  FrameTap tap_;
  std::int64_t last_synced_t_ns_ = 0;
  std::string what_;  // "ONI file 'x'" / "OpenNI2 device 'x'", for messages
  DeviceStateMachine machine_;
  std::atomic<DeviceState> state_{DeviceState::kOpening};
  static constexpr std::size_t kFaultTextBytes = 384;
  std::array<char, kFaultTextBytes> fault_text_{};  // written by the thread before end_of_stream_
  std::atomic<bool> is_file_{false};
  std::atomic<bool> registered_{false};
  std::uint64_t clip_depth_frames_ = 0;  // playback: frames per stream in the clip
  std::uint64_t clip_colour_frames_ = 0;

  rt::SingleWriterCounter depth_read_;
  rt::SingleWriterCounter colour_read_;
  rt::SingleWriterCounter frames_read_;
  rt::SingleWriterCounter delivered_;
  rt::SingleWriterCounter dropped_ring_full_;
  rt::SingleWriterCounter dropped_pool_empty_;
  rt::SingleWriterCounter unpaired_;
  rt::SingleWriterCounter size_mismatch_;
  rt::SingleWriterCounter read_errors_;
  rt::SingleWriterCounter timeouts_;
  rt::SingleWriterCounter clock_reanchors_;
  rt::SingleWriterCounter playback_skipped_;
  rt::SingleWriterCounter reopens_;
  std::atomic<bool> end_of_stream_{false};
  static constexpr std::int64_t kNoAnchor = INT64_MIN;
  std::atomic<std::int64_t> host_minus_device_ns_{kNoAnchor};
  std::optional<PinnedStackThread> thread_;
};

}  // namespace vigs::drivers
