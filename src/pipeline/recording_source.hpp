#pragma once
// RecordingSource: an MCAP recording presented to the live pipeline the way the drivers
// present a sensor: a thread (the table's rgbd_driver entry) copies each frame into a FramePool
// slot (raw 16-bit depth, rgb8) and pushes its handle into the frame ring, after pushing every
// IMU sample stamped at or before it into the IMU ring; stamps stay the recording's.
//  - real time: paced by the stamps (frame k at start + (t_k - t_0)); full rings drop the
//    newest element and count it, an empty pool drops the frame, as the drivers do;
//  - lockstep: no pacing and no drops: it waits for room, each wait bounded by wait_timeout_ns
//    (then it fails with a message naming the ring instead of hanging).
// The end of the recording is an invalid FrameHandle (the drivers' end marker). Reading
// errors end the stream too, with error() naming the file.
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include "core/types/imu_sample.hpp"
#include "core/types/pinhole_camera.hpp"
#include "rt/counters.hpp"
#include "rt/frame_pool.hpp"
#include "rt/rt_thread.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::pipeline {

struct RecordingSourceSettings {
  std::string path;
  bool lockstep = false;
  std::int64_t wait_timeout_ns = 30'000'000'000;
  float depth_scale_m = 0.001f;  ///< metres per raw unit written into the pool
  std::int64_t max_frames = 0;   ///< 0 = all
  rt::ThreadSpec thread;         ///< rgbd_driver with the rt policy applied
};

struct RecordingSourceCounters {
  std::uint64_t frames = 0;
  std::uint64_t imu_samples = 0;
  std::uint64_t frame_drops = 0;  ///< ring full or pool empty (real time only)
  std::uint64_t imu_drops = 0;
};

class RecordingSource {
 public:
  /// The camera of the recording's first frame (its size sizes the FramePool); throws
  /// RecordingError naming the file when it has no frames.
  static PinholeCamera first_camera(const std::string& path, std::int64_t* first_t_ns = nullptr);
  /// How many colour frames the recording holds (from its summary's message counts; without
  /// an intact summary, by scanning the colour topic's messages, not decoding them).
  static std::uint64_t frame_count(const std::string& path);

  RecordingSource(const RecordingSourceSettings& s, rt::FramePool& pool,
                  rt::SpscRing<rt::FrameHandle>& frames, rt::SpscRing<ImuSample>& imu);
  ~RecordingSource();
  RecordingSource(const RecordingSource&) = delete;
  RecordingSource& operator=(const RecordingSource&) = delete;

  /// The recording's camera (read at construction; throws naming the file when it has no
  /// frames or its frames do not fit the pool).
  [[nodiscard]] const PinholeCamera& camera() const noexcept { return camera_; }
  /// Stamp of the first frame.
  [[nodiscard]] std::int64_t first_t_ns() const noexcept { return first_t_ns_; }
  /// CLOCK_MONOTONIC of the first frame's push in real time (0 before).
  [[nodiscard]] std::int64_t start_mono_ns() const noexcept { return start_mono_ns_.load(); }

  void start();
  void stop();
  [[nodiscard]] bool ended() const noexcept { return ended_.load(std::memory_order_acquire); }
  /// Empty, or why the stream ended early (after ended()).
  [[nodiscard]] const std::string& error() const noexcept { return error_; }
  [[nodiscard]] RecordingSourceCounters counters() const noexcept;

 private:
  void run(const std::stop_token& stop);
  template <class Pred>
  bool push(const std::stop_token& stop, Pred&& try_once, const char* what);

  RecordingSourceSettings s_;
  rt::FramePool& pool_;
  rt::SpscRing<rt::FrameHandle>& frames_;
  rt::SpscRing<ImuSample>& imu_;
  PinholeCamera camera_;
  std::int64_t first_t_ns_ = 0;
  std::atomic<std::int64_t> start_mono_ns_{0};
  std::atomic<bool> ended_{false};
  std::string error_;
  rt::SingleWriterCounter frames_out_, imu_out_, frame_drops_, imu_drops_;
  std::optional<rt::RtThread> thread_;
};

}  // namespace vigs::pipeline
