#pragma once
// The odometry front end: one InertialFrontend and one Tracker, driven frame by frame.
//
// Fusion (tracking.fusion, imu mode only): `paper` is the scheme below (VIGS as published);
// `fused` (the default since 2026-12-04: BENCHMARKS.md, issue #11) hands the tracker the
// IMU-predicted camera pose with its covariance from a 15-state filter
// (inertial/state_propagation.hpp) as a prior factor of GICP's least squares, and updates the
// filter — pose, velocity, gyro and accelerometer bias — from the fused result and its
// information.
//
// With InitialGuessMode::imu each frame's GICP starts from the IMU-propagated pose the
// InertialFrontend composes (VIGS: T_w_c(k) = T_w_c(k-1) · T_c_b · T_b(k-1→k) · T_b_c). After a
// frame whose pose came from GICP the integrator is reset from it (R, p and v = Δp/Δt, the
// paper's reset). After a tracking failure it is NOT reset: the next prediction keeps
// integrating from the last good frame, so a run of lost frames is bridged by the IMU and each
// of them is reported with pose_from_gicp = false. constant_velocity and previous_pose ignore
// the IMU (the no-IMU baselines; GS-ICP SLAM uses previous_pose).
//
// World frame: the InertialFrontend integrates with gravity (0, 0, -g), so the world must be
// gravity-aligned with z up. The first frame's pose is `initial_T_w_c` when given (e.g. the
// recording's ground truth at that frame, or an attitude from the accelerometer at rest, see
// inertial/gravity_alignment.hpp). Without it the first camera frame is the world frame; for
// a level camera (optical axis horizontal) that world is not z-up, so imu mode then predicts
// with gravity along the wrong axis. The baselines do not care.
//
// Single-threaded. After construction, add_imu() does not allocate; track() allocates no more
// than Tracker::track() itself.
#include <cstdint>
#include <optional>
#include <string>

#include "core/config/robot_config.hpp"
#include "core/types/imu_sample.hpp"
#include "core/types/pinhole_camera.hpp"
#include "core/types/rgbd_view.hpp"
#include "inertial/inertial_frontend.hpp"
#include "tracking/tracker.hpp"

namespace vigs::pipeline {

/// "imu", "constant_velocity" or "previous_pose" (the names tracking.initial_guess accepts).
const char* to_string(tracking::InitialGuessMode mode);

/// How the IMU and GICP are combined in imu mode (tracking.fusion).
enum class FusionMode {
  fused,  ///< IMU prediction + covariance as a GICP prior; 15-state filter updated from it
  paper,  ///< VIGS: IMU guess, then reset from GICP (v = dp/dt, slow gyro-bias update)
};
const char* to_string(FusionMode mode);
/// "fused" or "paper"; false for anything else.
bool parse_fusion_mode(const std::string& name, FusionMode& out);

struct OdometryOptions {
  /// Overrides tracking.initial_guess from the configuration when set.
  std::optional<tracking::InitialGuessMode> guess;
  /// Overrides tracking.fusion when set.
  std::optional<FusionMode> fusion;
  /// Camera pose of the first frame in the gravity-aligned (z-up) world; identity when unset.
  std::optional<geometry::Pose> initial_T_w_c;
  /// Overrides member 1 of the tracker's worker team (tracking::Tracker::Setting::worker)
  /// when set: the live pipeline passes the thread table's `tracker_w1` (its priority, on the
  /// CPU the tracker does not use) as rt: allows.
  std::optional<rt::ThreadSpec> worker;
};

/// One frame's result.
struct TrackedFrame {
  std::int64_t t_ns = 0;
  geometry::Pose T_w_c = geometry::Pose::Identity();        ///< the frame's pose estimate
  geometry::Pose T_w_c_guess = geometry::Pose::Identity();  ///< where GICP started
  tracking::TrackingStatus status = tracking::TrackingStatus::initialized;
  bool pose_from_gicp = false;  ///< false: T_w_c is the guess (IMU-propagated in imu mode)
  bool imu_guess = false;       ///< the guess came from the IMU (imu mode with a prediction)
  bool keyframe = false;
  bool held = false;  ///< became a held keyframe, released later (tracking::TrackingOutput::held)
  bool reinitialized = false;  ///< the local map restarted here (TrackingOutput::reinitialized)
  double inlier_ratio = 0.0;
  int gicp_iterations = 0;
  tracking::GicpVerdict gicp_verdict = tracking::GicpVerdict::diverged;  ///< (first: diverged)
  bool prior_used = false;  ///< fused: GICP had the IMU prior
  bool degenerate = false;  ///< GICP alone had a degenerate direction
  int moving_points = 0;    ///< keyframe points rejected as moving
  /// Pose covariance, row-major 6x6 in vigs::PoseSample's order [x y z rx ry rz] (m, rad):
  /// translation of the camera position and rotation about it, both in world axes. From the
  /// tracker's (fused: posterior) information; valid only when covariance_valid.
  double covariance[36] = {};
  bool covariance_valid = false;
};

struct OdometryCounters {
  long frames = 0;
  long tracked = 0;  ///< pose from GICP (status tracked) that converged
  /// Pose from GICP (status tracked) that hit max_iterations before converging: used like a
  /// tracked pose, counted apart from `tracked` (frames = 1 + tracked + not_converged + lost).
  long not_converged = 0;
  long degenerate = 0;        ///< frames whose GICP alone had a degenerate direction
  long moving_points = 0;     ///< keyframe points rejected as moving, summed
  long lost = 0;              ///< any lost_* status
  long lost_low_inliers = 0;  ///< by status
  long lost_diverged = 0;
  long lost_degenerate = 0;
  long keyframes = 0;
  long reinitializations = 0;  ///< local map restarts after reinit_after_lost_frames lost frames
  long imu_resets = 0;         ///< reset_from_tracked calls
  long imu_guesses = 0;        ///< frames whose guess came from the IMU
  long imu_unavailable = 0;    ///< imu mode but no prediction (tracker fell back)
  long fused_updates = 0;      ///< fused mode: filter updates (incl. the start)
  long zero_velocity_updates = 0;  ///< fused mode: updates whose interval the IMU showed still
  long zupt_gated = 0;  ///< fused mode: still by the IMU, but the zero-velocity update was gated
};

class Odometry {
 public:
  /// Settings from cfg.tracking (settings_from_config.hpp) and cfg.imu / extrinsics / inertial
  /// (InertialFrontendOptions::from); `camera` is the recorded camera's intrinsics.
  Odometry(const config::RobotConfig& cfg, const PinholeCamera& camera,
           const OdometryOptions& options = {});

  /// Queues one IMU sample (body frame, recording clock). Returns false if refused (older than
  /// the last one queued).
  /// In constant_velocity and previous_pose mode samples are ignored (returns true).
  bool add_imu(const ImuSample& sample) {
    return mode_ != tracking::InitialGuessMode::imu || inertial_.add_sample(sample);
  }

  /// Tracks the frame at frame.t_ns. Feed every IMU sample with t <= frame.t_ns first.
  TrackedFrame track(const RgbdView& frame);

  [[nodiscard]] tracking::InitialGuessMode guess_mode() const { return mode_; }
  [[nodiscard]] FusionMode fusion_mode() const { return fusion_; }
  [[nodiscard]] const OdometryCounters& counters() const { return counters_; }
  [[nodiscard]] const tracking::Tracker& tracker() const { return tracker_; }
  [[nodiscard]] const inertial::InertialFrontend& inertial() const { return inertial_; }

 private:
  tracking::InitialGuessMode mode_;
  FusionMode fusion_ = FusionMode::fused;
  std::optional<geometry::Pose> initial_T_w_c_;
  inertial::InertialFrontend inertial_;
  tracking::Tracker tracker_;
  OdometryCounters counters_;
};

}  // namespace vigs::pipeline
