// V4l2RgbdDriver: an RGB-D source made of two V4L2 capture nodes -- a depth node (Z16) and a
// colour node (YUYV, MJPEG or GREY), as RealSense-class UVC cameras appear -- read on one
// real-time thread, paired by kernel timestamp, copied into a FramePool slot and pushed as a
// FrameHandle, like Openni2Driver.
//
// Thread: rt thread table entry `rgbd_driver`, created by start(), joined by stop(). Loop: poll()
// both fds (wait_timeout_ms, so stop() returns within about that), drain each ready node with
// non-blocking VIDIOC_DQBUF, pair by kernel timestamp (FramePairer; tolerance
// pair_tolerance_us, default half a frame period: frames of one instant pair, neighbours never
// do; the older of two that do not pair is unpaired and counted), then acquire a pool slot, copy
// Z16 into the depth plane (row by row: bytesperline may pad), convert the colour buffer into the
// colour plane (libv4lconvert to rgb8; GREY into a 1-channel pool is a copy), stamp with the
// depth buffer's kernel timestamp (forced strictly increasing), push, and requeue both buffers.
// A buffer is held by the driver only while it waits for its partner.
//
// Ring policy (as OpenNI2): push_or_drop: a full ring drops the newest pair (its slot goes back
// to the pool at once, dropped_ring_full); an empty pool drops the pair (dropped_pool_empty).
// The driver never waits for the consumer.
//
// Life cycle: DeviceStateMachine (drivers/common): the pair is one device. ENODEV from either
// node (unplugged), no frame for frame_timeout_ms, or max_consecutive_errors failures in a row
// lose the stream: both nodes are closed and reopened by path with a backoff (100 ms doubling to
// 2 s), so a stable /dev/v4l/by-id/ name survives a re-plug. start() opens both itself and
// throws V4l2Error naming the node (unless wait_for_device).
//
// Real-time: after open the loop only polls, issues ioctls on preallocated structs, copies and
// converts (libv4lconvert keeps its buffers; MJPEG decoding allocates inside libjpeg). Opening
// and reopening allocate (a recovery path).
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include "drivers/common/device_state_machine.hpp"
#include "drivers/common/frame_pairer.hpp"
#include "drivers/common/frame_tap.hpp"
#include "drivers/common/rgbd_driver_counters.hpp"
#include "drivers/common/trigger_matcher.hpp"
#include "drivers/v4l2/v4l2_capture.hpp"
#include "drivers/v4l2/v4l2_device_ops.hpp"
#include "rt/counters.hpp"
#include "rt/frame_pool.hpp"
#include "rt/rt_thread.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::config {
struct CameraSettings;
struct RtSettings;
}  // namespace vigs::config

namespace vigs::drivers {

struct V4l2RgbdDriverSettings {
  std::string depth_device;   ///< Z16 node
  std::string colour_device;  ///< YUYV / MJPEG / GREY node
  V4l2PixelFormat colour_format = V4l2PixelFormat::kYuyv;
  std::uint32_t width_px = 640;  ///< both nodes deliver this size (depth registered to colour)
  std::uint32_t height_px = 480;
  double rate_hz = 30.0;
  std::int64_t pair_tolerance_us = 0;  ///< 0: half a frame period
  std::uint32_t buffers = 4;           ///< mmap buffers per node
  int wait_timeout_ms = 20;            ///< poll timeout, bound on stop() latency
  int frame_timeout_ms = 1000;         ///< streaming without a pair's frame this long: lost
  int max_consecutive_errors = 10;
  int reopen_backoff_initial_ms = 100;
  int reopen_backoff_max_ms = 2000;
  bool reopen = true;
  bool wait_for_device = false;  ///< start() does not open: the thread keeps trying
  bool realtime_thread = true;
  bool pin_cpu = true;
};

/// Settings from the robot config: camera.device (depth node), camera.colour_device,
/// camera.colour_format, camera.width_px/height_px/rate_hz, rt.realtime_priorities, rt.pin_cpus.
[[nodiscard]] V4l2RgbdDriverSettings v4l2_rgbd_settings(const config::CameraSettings& camera,
                                                        const config::RtSettings& rt);

/// V4L2-specific counters beside the common RGB-D ones, summed over both nodes.
struct V4l2RgbdCounters {
  RgbdDriverCounters rgbd;            // same meaning as Openni2Driver's (clock_reanchors: 0)
  std::uint64_t kernel_dropped = 0;   // gaps in the kernel's sequence numbers
  std::uint64_t corrupt_buffers = 0;  // V4L2_BUF_FLAG_ERROR
  std::uint64_t eagain = 0;           // woken, nothing to dequeue
  std::uint64_t convert_errors = 0;   // colour buffers libv4lconvert refused (pair dropped)
  std::uint64_t host_stamped = 0;     // buffers without a monotonic kernel timestamp
};

class V4l2RgbdDriver {
 public:
  /// `pool`: width_px x height_px, 3 colour channels (1 allowed for GREY). `ops` is the device
  /// seam (libv4l2_device_ops() for real devices). All references must outlive the driver.
  V4l2RgbdDriver(const V4l2RgbdDriverSettings& settings, rt::FramePool& pool,
                 rt::SpscRing<rt::FrameHandle>& out, V4l2DeviceOps& ops = libv4l2_device_ops());
  ~V4l2RgbdDriver();
  V4l2RgbdDriver(const V4l2RgbdDriver&) = delete;
  V4l2RgbdDriver& operator=(const V4l2RgbdDriver&) = delete;

  /// Frame sync: each pair's stamp becomes its GPIO edge's (TriggerMatcher; set before start(),
  /// used on the driver thread only). Pairs are matched in the order they are formed, also those
  /// then dropped, so the edges stay in step.
  void set_trigger(TriggerMatcher* matcher) noexcept { trigger_ = matcher; }
  /// The recorder's tap (drivers/common/frame_tap.hpp); set before start().
  void set_tap(rt::SpscRing<rt::FrameHandle>* tap) noexcept { tap_.set(tap); }
  void start();
  void stop();
  [[nodiscard]] bool running() const noexcept { return thread_.has_value(); }
  /// The stream ended for good (a final fault: reopen off or exhausted). Then the end-of-stream
  /// marker (an invalid handle) follows the last frame in the ring.
  [[nodiscard]] bool end_of_stream() const noexcept {
    return end_of_stream_.load(std::memory_order_acquire);
  }
  [[nodiscard]] DeviceState state() const noexcept {
    return state_.load(std::memory_order_acquire);
  }
  [[nodiscard]] V4l2RgbdCounters counters() const noexcept;
  [[nodiscard]] const rt::ThreadApplyStatus* thread_status() const noexcept;

 private:
  static constexpr int kDepth = 0;
  static constexpr int kColour = 1;
  void open_nodes();  // throws V4l2Error; both closed after a throw
  void close_nodes() noexcept;
  void run(const std::stop_token& stop) noexcept;
  void stream_step() noexcept;
  void drain(int s) noexcept;
  void on_buffer(int s, const V4l2Buffer& b) noexcept;
  void emit_pair() noexcept;
  void requeue_pending(int s) noexcept;
  void finish_stream(const std::stop_token& stop) noexcept;

  V4l2RgbdDriverSettings settings_;
  rt::FramePool& pool_;
  rt::SpscRing<rt::FrameHandle>& out_;
  V4l2DeviceOps& ops_;
  V4l2Capture nodes_[2];
  FramePairer pairer_;
  DeviceStateMachine machine_;
  std::optional<V4l2Buffer> pending_[2];
  TriggerMatcher* trigger_ = nullptr;
  FrameTap tap_;
  std::int64_t last_t_ns_ = 0;
  std::atomic<DeviceState> state_{DeviceState::kOpening};
  std::atomic<bool> end_of_stream_{false};
  rt::SingleWriterCounter depth_read_, colour_read_, frames_read_, delivered_, dropped_ring_full_,
      dropped_pool_empty_, unpaired_, size_mismatch_, read_errors_, timeouts_, reopens_,
      convert_errors_;
  rt::SingleWriterCounter eagain_;
  // Capture counters of nodes closed by a loss (a node's own counters restart at each open).
  rt::SingleWriterCounter kernel_dropped_, corrupt_, host_stamped_;
  std::optional<rt::RtThread> thread_;
};

}  // namespace vigs::drivers
