#pragma once
// Lockstep replay of an MCAP recording through the Odometry: nothing is dropped and nothing
// waits on a clock, so the same file and configuration give a bit-identical trajectory (the
// tracker's threads use a fixed partition).
//
// Order: the IMU and ground truth are read first (recorded_motion.hpp; a damaged file is
// refused there), then the frames are streamed (io::for_each_recorded_frame) and before each
// frame every IMU sample with t <= the frame stamp is fed, in stamp order.
//
// The first frame's pose (the world frame must be gravity-aligned, z up, for the IMU):
//  - gravity (default, ReplayOptions::initial_pose): the attitude from the mean accelerometer
//    reading of the IMU samples in the 0.5 s up to the first frame (the sensor must be at rest
//    then; yaw 0, position 0), so no ground truth enters the estimate;
//  - ground_truth (on request, for debugging; or when the recording has no IMU): the
//    recording's T_w_b at the first frame (interpolated) times T_b_c; the estimate then shares
//    the ground truth's world frame;
//  - identity: neither (fine for the no-IMU baselines only).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/config/robot_config.hpp"
#include "mapping/gaussian_map.hpp"
#include "mapping/mapper_memory.hpp"
#include "pipeline/odometry.hpp"
#include "pipeline/recorded_motion.hpp"
#include "tracking/loop_closure.hpp"

namespace vigs::pipeline {

/// Feeds the samples of a time-sorted vector into an Odometry, each once.
class ImuFeeder {
 public:
  explicit ImuFeeder(const std::vector<ImuSample>& imu) : imu_(imu) {}
  /// Adds every sample not yet fed with t_ns <= t_frame_ns; returns how many.
  std::size_t feed_until(std::int64_t t_frame_ns, Odometry& odometry);
  [[nodiscard]] std::size_t fed() const { return next_; }

 private:
  const std::vector<ImuSample>& imu_;
  std::size_t next_ = 0;
};

enum class InitialPoseSource { ground_truth, gravity, identity };
const char* to_string(InitialPoseSource source);

/// The accelerometer window that levels the first frame (gravity start): the samples of the
/// half second up to the frame, and when the IMU started with (or just before) the camera, the
/// first kMinRestSamples from the window's start, reaching past the frame (the gyro carries
/// them back to it, inertial/gravity_alignment.hpp). One sample is not enough: its noise alone
/// tilted the simulated office's start by 0.3 degrees (2.0e-3 m/s^2/sqrt(Hz) at 200 Hz).
inline constexpr std::int64_t kRestWindowNs = 500'000'000;
inline constexpr std::size_t kMinRestSamples = 40;

/// The first frame's camera pose from the recording (see the header comment); `used` says which.
/// `prefer` gravity: the ground truth is used only when there are no IMU samples.
geometry::Pose initial_camera_pose(const RecordedMotion& motion, std::int64_t t_first_ns,
                                   const config::RobotConfig& cfg, InitialPoseSource& used,
                                   InitialPoseSource prefer = InitialPoseSource::ground_truth);

/// Where the lockstep mapper places each keyframe: at the tracker's estimate (loop-corrected
/// with tracking.loop_closure and mapping.follow_loop_closures), or at the recording's
/// ground-truth camera pose at the keyframe's stamp. The second measures the mapper alone,
/// without tracking error (the map is then in the ground truth's world frame, and `vigs eval
/// run` renders it at the ground-truth poses: stats.json map_poses).
enum class MapPoseSource { estimate, ground_truth };
const char* to_string(MapPoseSource source);

struct ReplayOptions {
  std::optional<tracking::InitialGuessMode> guess;  ///< overrides tracking.initial_guess
  std::optional<FusionMode> fusion;                 ///< overrides tracking.fusion
  std::int64_t max_frames = 0;                      ///< 0 = every frame
  /// gravity: start from the gravity-aligned attitude at rest (no ground truth in the estimate);
  /// ground_truth: from the recording's ground truth (debugging).
  InitialPoseSource initial_pose = InitialPoseSource::gravity;
  /// > 0: build a Gaussian map in lockstep (lockstep_mapping.hpp) with this many mapper
  /// iterations after every frame; 0: no map.
  int map_iterations_per_frame = 0;
  /// > 0: build the map with this mapper time budget per frame instead (mapping.budget_ms;
  /// overrides map_iterations_per_frame; the iteration count then follows the wall clock).
  double map_budget_ms = 0.0;
  /// Keyframe poses the map is built at (with mapping on). ground_truth needs a ground-truth
  /// pose within 50 ms of every keyframe (RecordingError naming the stamp otherwise).
  MapPoseSource map_poses = MapPoseSource::estimate;
  std::string imu_topic{io::topics::kImu.name};
  std::string pose_topic{io::topics::kBodyPose.name};
  /// Replay the intact part of a damaged recording (ReplayResult::damage says what was found)
  /// instead of refusing it.
  bool allow_damaged = false;
  /// Replay as the recording's own run did (`vigs run --record`: /vigs/pose/imu_used): track
  /// only the frames it tracked (a live tracker skips to the newest frame and releases frames
  /// before the IMU's first sample), each with the IMU samples up to the newest one it had
  /// used (an IMU the tracker found late). Gives that run's trajectory bit for bit.
  bool as_run = false;
  /// Start this many frames late: the first N frames (of those tracked with as_run) are not
  /// tracked and their IMU samples go in before the first tracked frame, as in a live run
  /// whose tracker found its first frame late. A start-offset sweep shows how much a result
  /// depends on the exact start (toolchain/bench-start-sweep).
  std::int64_t skip_frames = 0;
};

struct ReplayResult {
  std::vector<TrackedFrame> frames;
  OdometryCounters counters;
  tracking::InitialGuessMode guess = tracking::InitialGuessMode::imu;
  InitialPoseSource initial_pose = InitialPoseSource::identity;
  PinholeCamera camera;
  std::size_t imu_samples = 0;                 ///< in the recording
  std::size_t imu_samples_fed = 0;             ///< fed before the last replayed frame
  std::int64_t frames_without_depth = 0;       ///< tracked with an all-invalid depth image
  std::int64_t frames_not_tracked_by_run = 0;  ///< as_run: recorded frames the run did not track
  std::int64_t frames_skipped_at_start = 0;    ///< skip_frames: frames not tracked at the start
  /// Keyframes not given to the mapper because their frame was no longer kept (none expected).
  std::int64_t keyframes_without_view = 0;
  io::mcap::DamageReport damage;  ///< with allow_damaged: what the readers found
  double wall_s = 0.0;            ///< whole replay: reading, decoding, tracking
  double track_s = 0.0;           ///< inside Odometry::track only
  std::vector<float> track_ms;    ///< per frame, inside Odometry::track
  FusionMode fusion = FusionMode::fused;
  /// The map after the last frame's mapper tick (null without mapping).
  std::shared_ptr<const mapping::GaussianMap> map;
  long map_iterations = 0;
  long map_coarse_iterations = 0;                     ///< of map_iterations: at half resolution
  double map_s = 0.0;                                 ///< inside the mapper
  double map_budget_ms = 0.0;                         ///< the mapper's budget per frame (0 = none)
  MapPoseSource map_poses = MapPoseSource::estimate;  ///< where keyframes went into the map
  std::uint64_t map_budget_overruns = 0;              ///< mapper ticks past their (carried) budget
  double map_bytes_per_gaussian = 0.0;                ///< map_memory.bytes_per_gaussian()
  mapping::MapperMemory map_memory;                   ///< the mapper's memory by owner at the end
  std::uint64_t map_gated_points = 0;                 ///< keyframe points the map already rendered
  std::uint64_t map_seen_through_pruned = 0;          ///< Gaussians later keyframes saw through
  std::uint64_t map_refined_closer = 0;               ///< Gaussians replaced when seen from closer
  std::uint64_t map_nonfinite_gradients = 0;  ///< Gaussian gradients not applied: not finite
  std::uint64_t map_moved_by_loops = 0;  ///< Gaussians moved with their keyframe by loop closures
  /// tracking.loop_closure: `frames` hold the loop-corrected poses, `frames_odometry` the
  /// poses as the odometry tracked them (same order); `loop` what the loop closer did.
  std::optional<tracking::LoopClosureStats> loop;
  std::vector<geometry::Pose> frames_odometry;
};

/// Solves the loop closer's graph and makes r.frames the corrected trajectory, keeping the
/// poses as tracked in r.frames_odometry and the closer's counts in r.loop (vigs replay and
/// vigs run, whose frames and keyframes share one clock when this is called).
void apply_loop_closure(tracking::LoopCloser& loops, ReplayResult& r);

/// Replays `path`. Throws RecordingError naming the file on a damaged or unusable recording
/// (no frames, frames changing size, undecodable messages, no IMU samples in imu mode); an
/// unreadable file too. `on_frame` (optional) sees every result as it is made.
ReplayResult replay_recording(const std::string& path, const config::RobotConfig& cfg,
                              const ReplayOptions& options,
                              const std::function<void(const TrackedFrame&)>& on_frame = {});

}  // namespace vigs::pipeline
