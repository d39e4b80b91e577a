#pragma once
// The live pipeline, `vigs run`: driver threads -> lock-free rings -> fixed-rate tracker and
// mapper tasks -> DDS publisher. live_pipeline.cpp is the spine: read it top to bottom.
//
// Threads (rt/thread_table.hpp, with rt.realtime_priorities / rt.pin_cpus applied):
//   rgbd_driver, imu_driver  the sources: the robot's camera (camera.driver openni2 or v4l2:
//                            live_camera.hpp) and serial IMU, or an MCAP recording played
//                            into the same rings (RecordingSource), or
//                            (through_drivers) that recording as an .oni clip and Xsens bytes
//                            on a pty read by the same two real drivers (DriverReplay, with
//                            its feeder thread); results then in the recording's clock
//   tracker (+ tracker_w1)   LiveTracker at camera.rate_hz (lockstep: every 1 ms, all frames)
//   mapper (+ mapper_w1)     LiveMapper at mapping.rate_hz (when mapping)
//   dds_pub                  dds::PosePublisher draining the pose ring; status at 1 Hz
//   the calling thread       collects results, fills the status mailbox, progress, stop
//   sensor_replay            through_drivers: DriverReplay's feeder (the IMU bytes on the pty)
//   recorder                 with record_path: record::Recorder draining its own tap ring from
//                            each driver (frames, IMU samples, the serial port's raw bytes) and
//                            the poses the main thread collects, into a crash-safe MCAP
//   gpio_trigger             live, with camera.trigger_chip: the camera's frame-sync edges,
//                            which restamp its frames (LiveCamera: GpioTrigger, TriggerMatcher)
// Rings: frames (FramePool handles; capacity the largest power of two <= rt.frame_pool_slots
// - 4, so a slot is always left for the driver, the tracker and the mapper's keyframes), IMU
// (rt.imu_ring_capacity), poses (256), results (1024), keyframes (KeyframeHandoff, 2 slots).
// Lockstep: nothing drops; every producer waits for its consumer (bounded by wait_timeout_ns,
// then the run fails with a message naming the stage); two runs give the same trajectory.
// Stop: the source's end of stream (an invalid frame handle) flows through the tracker (which
// then queues the end marker for the mapper and the main thread), or `stop` becomes non-zero
// (SIGINT/SIGTERM): the sources stop, the rings are drained, the tasks joined.
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/config/robot_config.hpp"
#include "drivers/common/rgbd_driver_counters.hpp"
#include "drivers/common/trigger_matcher.hpp"
#include "drivers/gpio_trigger/gpio_trigger.hpp"
#include "drivers/serial_imu/serial_imu_faults.hpp"
#include "pipeline/driver_replay.hpp"
#include "pipeline/live_camera.hpp"
#include "pipeline/live_tracker.hpp"
#include "pipeline/lockstep_replay.hpp"
#include "pipeline/recording_source.hpp"
#include "record/recorder.hpp"

namespace vigs::pipeline {

struct LiveOptions {
  std::string recording;         ///< MCAP played into the rings; empty: the robot's live sensors
  bool through_drivers = false;  ///< recording: through the real drivers (DriverReplay)
  DriverReplayFaults driver_faults;  ///< through_drivers: faults the feeder injects (tests)
  std::string config_path;           ///< for dds.qos_profiles; empty: the built-in configuration
  bool lockstep = false;
  bool mapping = true;
  std::int64_t max_frames = 0;  ///< recording: 0 = all
  std::int64_t wait_timeout_ns = 30'000'000'000;
  std::optional<int> dds_domain;           ///< overrides dds.domain_id (tests)
  const std::atomic<int>* stop = nullptr;  ///< non-zero: stop (a signal handler's flag)
  /// Before the sources start, wait (up to 30 s, else throw) for this many pose subscribers.
  int wait_for_subscribers = 0;
  /// Non-empty: record while running (`vigs run --record`). Needs the drivers (live, or a
  /// recording through_drivers). Written as PATH.partial (crash-safe, chunked: a kill leaves a
  /// readable prefix there) and renamed onto PATH once the recorder has closed it.
  std::string record_path;
  /// Live: the camera's kernel seams (tests: a fake V4L2 device, a pipe of GPIO events); the
  /// defaults are the real ones.
  LiveCameraSeams camera_seams;
};

/// `vigs run --record`: what the recorder wrote and what its taps dropped (full tap: the
/// newest item is dropped and counted; no driver or the tracker ever waits for the recorder).
struct LiveRecordResult {
  std::string file;
  record::RecorderStats written;
  std::uint64_t frame_tap_drops = 0, imu_tap_drops = 0, serial_tap_drops = 0;
  std::uint64_t pose_tap_drops = 0;
  std::uint64_t edge_tap_drops = 0;  ///< the GPIO trigger's edges (with camera.trigger_chip)
  [[nodiscard]] std::uint64_t tap_drops() const noexcept {
    return frame_tap_drops + imu_tap_drops + serial_tap_drops + pose_tap_drops + edge_tap_drops;
  }
};

struct LiveProgress {
  std::uint64_t frames = 0;  ///< tracked
  /// Frames the source has played so far (tracked, skipped or dropped): the ETA's rate.
  std::uint64_t frames_played = 0;
  /// A recording: the frames it will play (its frame count, or --frames); 0: live (no end).
  std::uint64_t frames_total = 0;
  double elapsed_s = 0;
  double stream_s = 0;  ///< sensor time covered
  std::int64_t track_p50_ns = 0, track_p99_ns = 0;
  std::uint64_t drops = 0;  ///< every ring and pool drop
  std::size_t gaussians = 0;
  bool recording = false;  ///< --record: the two below are the recorder's
  double record_mb = 0;
  std::uint64_t record_drops = 0;
};

struct LatencyQuantiles {
  std::int64_t p50_ns = 0, p99_ns = 0;
  std::size_t count = 0;  ///< frames measured
};

struct LiveResult {
  ReplayResult replay;  ///< frames, counters, camera, map (for the RESULTS_DIR writer)
  LiveTrackerCounters tracker;
  std::vector<std::uint32_t> pose_flags;  ///< PoseFlags of each published pose (replay.frames)
  RecordingSourceCounters source;         ///< through_drivers: from the drivers' counters
  std::optional<drivers::RgbdDriverCounters> camera_driver;    ///< live, through_drivers
  std::optional<drivers::SerialImuFaults> imu_driver;          ///< live, through_drivers
  std::optional<drivers::GpioTriggerCounters> trigger;         ///< live with camera.trigger_chip
  std::optional<drivers::TriggerMatchCounters> trigger_match;  ///< ditto: frames to edges
  DriverReplayCounters feeder;                                 ///< through_drivers
  /// through_drivers: host CLOCK_MONOTONIC minus recording time. The published poses carry
  /// host stamps; `replay.frames` were mapped back to the recording's clock with it.
  std::int64_t host_minus_recording_ns = 0;
  std::uint64_t poses_published = 0;
  std::uint64_t status_published = 0;
  std::uint64_t tracker_cycles = 0, tracker_overruns = 0, tracker_missed = 0;
  /// Tracker overruns between the two frames real_time_factor_steady is measured between;
  /// unset with fewer than 3 frames.
  std::optional<std::uint64_t> tracker_overruns_steady;
  std::int64_t cycle_p50_ns = 0, cycle_p99_ns = 0;  ///< tracker task body
  std::int64_t track_p50_ns = 0, track_p99_ns = 0;  ///< Odometry::track
  /// Real time: a frame's arrival in the ring (the driver's CLOCK_MONOTONIC) to its pose in
  /// the publisher's ring (DDS adds its transport; `vigs echo --receipt` measures that end),
  /// and arrival to the tick that took it (the wait the phase lock shortens).
  LatencyQuantiles pose_latency_ns, frame_wait_ns;
  std::uint64_t tracker_phase_shift_ns = 0;  ///< how far the phase lock moved the ticks
  std::uint64_t drops = 0;
  double stream_s = 0;          ///< first to last frame stamp
  double real_time_factor = 0;  ///< stream_s / wall time from the first frame
  /// The same between the frames at 10 % and 90 % of the run (steady_rate.hpp); unset with
  /// fewer than 3 frames.
  std::optional<double> real_time_factor_steady;
  std::string memory_lock;  ///< "applied", "refused", "not requested"
  /// The tracker's worker team member 1 as it ran (unset: the odometry never started, or a
  /// team of one): its spec after rt: and what the OS applied.
  std::optional<rt::ThreadSpec> tracker_worker;
  rt::ThreadApplyStatus tracker_worker_status;
  /// The DDS publisher thread's spec after rt: (unset: the publisher never started).
  std::optional<rt::ThreadSpec> publisher_thread;
  bool stopped_by_signal = false;
  std::optional<LiveRecordResult> record;  ///< with record_path
};

/// Runs the pipeline until the stream ends or *options.stop. `progress` (optional) is called
/// about twice a second from the calling thread. Throws std::runtime_error naming the stage or
/// file on failure (a lockstep wait that timed out, an unreadable recording, a device).
LiveResult run_live(const config::RobotConfig& cfg, const LiveOptions& options,
                    const std::function<void(const LiveProgress&)>& progress = {});

}  // namespace vigs::pipeline
