#pragma once
// LiveTracker: the body of the live pipeline's `tracker` task (rt::PeriodicTask at
// camera.rate_hz). Each tick:
//  0. (real time) slides its own ticks toward just after the frames' arrival (rt/phase_lock.hpp,
//     rt.tracker_phase_lock): the task keeps camera.rate_hz, but a frame no longer waits up to
//     a whole period in the ring before the tracker looks at it;
//  1. takes the newest frame handle from the driver's ring; older queued frames are released
//     and counted (skipped; the next pose is flagged kPoseFlagFramesSkipped). In lockstep it
//     takes every queued frame in order instead, and nothing is skipped;
//  2. moves the IMU samples with t <= the frame's stamp from the IMU ring into the Odometry,
//     first waiting (up to 10 ms; not in lockstep, nor while the IMU is stale) until the IMU
//     has delivered a sample after the stamp: the frame is then tracked with every sample up
//     to it whichever driver delivered first, as `vigs replay --as-run` of a `vigs run
//     --record` file does (a timeout is counted: imu_late);
//  3. tracks (Odometry::track on the FramePool slot's RgbdView, no copy);
//  4. pushes the PoseSample into the publisher's ring and the frame's result into the
//     trajectory ring (both: full -> drop newest and count; lockstep: wait for room), and a
//     keyframe into the KeyframeHandoff (no slot free -> drop and count; lockstep: wait) with
//     the keyframe's own frame: with the moving test on the tracker holds a keyframe for
//     moving_window_frames frames (TrackedFrame::held), so its frame stays retained in the pool
//     (a ring of Tracker::held_capacity() handles) until the tracker releases the keyframe.
// Start-up (allocates once): the Odometry is made at the first frame that has IMU samples at or
// before its stamp (or, without any, the first 20 samples after it), with the gravity-aligned
// start of pipeline/lockstep_replay.hpp; earlier frames are released and counted (waiting_imu).
// Faults, counted and flagged in the pose: a frame stamped at or before the previous one is
// released (out_of_order, kPoseFlagOutOfOrder on the next pose); an IMU sample older than the
// last is refused by the Odometry (imu_refused); a frame without an IMU prediction is flagged
// kPoseFlagImuUnavailable, as is one whose newest IMU sample is over 100 ms older than it (the
// stream stopped: the IMU frontend extrapolates its last reading until samples return). The
// drivers' own faults (LiveTrackerSettings::driver_faults, counted on their threads) flag the
// first pose after their count grew: corrupt serial IMU bytes kPoseFlagImuCorrupt, a lost
// (and reopened) camera kPoseFlagCameraReopened; their counts at the first pose are the
// baseline (a port opened mid-stream skips bytes to its first header).
// Lockstep waits are bounded (wait_timeout_ns): a stage that does not move in that time fails
// the tracker with a message naming the ring instead of hanging.
// After warm-up the tick does not allocate, lock or log: the tracking buffers are sized for a
// whole frame when the Odometry is made (test_tracker_alloc counts operator new over 200
// frames on this thread and the tracker's worker).
#include <atomic>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/config/robot_config.hpp"
#include "core/types/imu_sample.hpp"
#include "core/types/pinhole_camera.hpp"
#include "core/types/pose_sample.hpp"
#include "pipeline/keyframe_handoff.hpp"
#include "pipeline/lockstep_replay.hpp"
#include "pipeline/odometry.hpp"
#include "rt/counters.hpp"
#include "rt/frame_pool.hpp"
#include "rt/phase_lock.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::pipeline {

/// One tracked frame as the main thread collects it.
struct LiveFrameResult {
  TrackedFrame frame;
  std::int64_t track_ns = 0;          ///< inside Odometry::track
  std::int64_t done_mono_ns = 0;      ///< CLOCK_MONOTONIC when the pose was pushed
  std::int64_t arrival_ns = 0;        ///< CLOCK_MONOTONIC when the driver queued the frame
  std::int64_t wake_ns = 0;           ///< the tracker tick that took it woke (0 in lockstep)
  std::uint32_t flags = 0;            ///< the published pose's PoseFlags
  bool end_of_stream = false;         ///< the last element: nothing follows
  std::int64_t imu_t_ns = INT64_MIN;  ///< newest IMU sample in the Odometry when tracked
};

/// A tracked frame's stamp, index and T_w_c (position and quaternion) as a PoseSample; no
/// covariance, velocity or flags (the tracker adds those to what it publishes).
PoseSample tracked_pose(const TrackedFrame& f, std::uint64_t index);

/// Fault totals the drivers keep on their own threads, which the tracker turns into pose flags:
/// it reads both once per pose and flags the pose when one has grown since the previous pose
/// (the first pose: since the tracker was made). Called on the tracker thread: monotonic
/// counts, and no allocation, lock or log (relaxed loads of the drivers' counters).
class DriverFaultCounts {
 public:
  virtual ~DriverFaultCounts() = default;
  /// Serial IMU bytes found corrupt (checksums failed, bytes skipped to resync, ...):
  /// kPoseFlagImuCorrupt.
  [[nodiscard]] virtual std::uint64_t imu_corrupt() const noexcept = 0;
  /// Camera streams lost (each then reopened): kPoseFlagCameraReopened.
  [[nodiscard]] virtual std::uint64_t camera_losses() const noexcept = 0;
};

struct LiveTrackerSettings {
  bool lockstep = false;
  std::int64_t wait_timeout_ns = 30'000'000'000;  ///< lockstep: bound on any wait
  float depth_scale_m = 0.001f;                   ///< metres per raw depth unit in the pool
  PinholeCamera camera;
  OdometryOptions odometry;  ///< guess / fusion overrides; initial_T_w_c unset = gravity
  /// Real time: phase-lock the ticks to the frames' arrival (rt.tracker_phase_lock; period 0 =
  /// off, and always off in lockstep). tick() then returns the next deadline's shift.
  rt::PhaseLockSettings phase_lock;
  /// The drivers' fault counts (null: no drivers, e.g. a recording played into the rings);
  /// must outlive the tracker.
  const DriverFaultCounts* driver_faults = nullptr;
};

struct LiveTrackerRings {
  rt::FramePool& pool;
  rt::SpscRing<rt::FrameHandle>& frames;   ///< driver -> tracker; invalid handle = end
  rt::SpscRing<ImuSample>& imu;            ///< driver -> tracker
  rt::SpscRing<PoseSample>& poses;         ///< tracker -> publisher
  rt::SpscRing<LiveFrameResult>& results;  ///< tracker -> main thread (trajectory, stats)
  KeyframeHandoff* keyframes;              ///< tracker -> mapper; null: no mapping
};

struct LiveTrackerCounters {
  std::uint64_t frames = 0;       ///< tracked
  std::uint64_t skipped = 0;      ///< older frames released for a newer one
  std::uint64_t waiting_imu = 0;  ///< frames released before the first IMU sample
  std::uint64_t out_of_order = 0;
  std::uint64_t imu_samples = 0;  ///< moved into the Odometry
  std::uint64_t imu_refused = 0;  ///< older than the previous sample
  std::uint64_t imu_unavailable = 0;
  std::uint64_t imu_late = 0;  ///< tracked before the IMU passed the frame (10 ms wait ran out)
  std::uint64_t pose_drops = 0;
  std::uint64_t result_drops = 0;
  std::uint64_t keyframes = 0;
  std::uint64_t keyframe_drops = 0;
};

class LiveTracker {
 public:
  LiveTracker(const config::RobotConfig& cfg, const LiveTrackerSettings& settings,
              const LiveTrackerRings& rings);

  /// The task body (tracker thread only); `wake_ns` is the tick's wake time. Returns the shift
  /// of the next deadline the phase lock asks for (0 without a fresh frame, in lockstep, or
  /// with the lock off): the pipeline hands it to rt::PeriodicTask::shift_next_deadline.
  std::int64_t tick(std::int64_t wake_ns = 0);

  /// The frame stream ended and every result (and the end markers) were pushed.
  [[nodiscard]] bool done() const noexcept { return done_.load(std::memory_order_acquire); }
  /// A lockstep wait timed out; failure_message() says which.
  [[nodiscard]] bool failed() const noexcept { return failed_.load(std::memory_order_acquire); }
  [[nodiscard]] const char* failure_message() const noexcept { return failure_; }
  /// Any thread, any time (relaxed snapshot).
  [[nodiscard]] LiveTrackerCounters counters() const noexcept;
  /// After the tracker thread has stopped: the Odometry's own counters (zero before the start).
  [[nodiscard]] OdometryCounters odometry_counters() const;
  /// After the tracker thread has stopped: member 1 of the odometry's worker team (null: no
  /// odometry yet, or a team of one).
  [[nodiscard]] const rt::RtThread* team_worker() const;
  [[nodiscard]] InitialPoseSource initial_pose() const noexcept { return initial_pose_; }

 private:
  bool take_frame(rt::FrameHandle& h) noexcept;
  void process(rt::FrameHandle h, std::int64_t wake_ns) noexcept;
  bool start_odometry(std::int64_t t_ns);
  void feed_imu(std::int64_t t_ns) noexcept;
  /// Before the Odometry exists: moves the samples up to t_ns into early_imu_ (for its start).
  void gather_early_imu(std::int64_t t_ns) noexcept;
  void await_imu(std::int64_t t_ns) noexcept;
  /// kPoseFlagImuCorrupt / kPoseFlagCameraReopened when the drivers' counts grew since the
  /// previous call.
  std::uint32_t driver_fault_flags() noexcept;
  void finish() noexcept;
  /// Mapping on: keeps a held keyframe's frame, and hands a released keyframe to the mapper
  /// with its own frame (this one, or the oldest kept one).
  void hand_keyframe(const TrackedFrame& f, rt::FrameHandle h) noexcept;
  void release_held_frames() noexcept;
  template <class Pred>
  bool wait(Pred&& ready, const char* what) noexcept;

  const config::RobotConfig& cfg_;
  LiveTrackerSettings s_;
  LiveTrackerRings r_;
  rt::PhaseLock phase_lock_;
  std::optional<Odometry> odometry_;
  std::vector<ImuSample> early_imu_;  // samples before the Odometry exists (reserved)
  std::size_t early_fed_ = 0;
  std::int64_t last_t_ns_ = INT64_MIN;
  std::int64_t last_imu_t_ns_ = INT64_MIN;  // newest IMU sample moved into the Odometry
  std::uint32_t pending_flags_ = 0;
  bool driver_faults_baseline_ = false;  // taken at the first pose
  std::uint64_t imu_corrupt_seen_ = 0;   // DriverFaultCounts at the previous pose
  std::uint64_t camera_losses_seen_ = 0;
  bool end_pending_ = false;  // the end marker was taken behind the frame being tracked
  std::uint64_t frame_index_ = 0;
  // Frames of the keyframes the tracker holds, oldest first, retained (made at start-up, room
  // for Tracker::held_capacity(); this thread is both ends).
  std::optional<rt::SpscRing<rt::FrameHandle>> held_frames_;
  InitialPoseSource initial_pose_ = InitialPoseSource::identity;
  std::atomic<bool> done_{false};
  std::atomic<bool> failed_{false};
  char failure_[160] = {};
  rt::SingleWriterCounter frames_, skipped_, waiting_imu_, out_of_order_, imu_samples_,
      imu_refused_, imu_unavailable_, imu_late_, pose_drops_, result_drops_, keyframes_;
};

}  // namespace vigs::pipeline
