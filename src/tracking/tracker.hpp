#pragma once
// The tracking front end for one RGB-D stream: each frame is turned into Gaussians, aligned
// by GICP against the bounded local map from the configured initial guess, checked for
// failure, and possibly made a keyframe (inserted into the local map and exposed for the
// mapper). Poses are T_w_c (camera in world). With the moving test on, a keyframe waits
// moving_window_frames frames for the frames after it before it is inserted; several can wait
// at once, so a quick turn keeps making keyframes.
//
// Failure: low inlier ratio, a diverged or degenerate GICP, or a correction of the guess
// beyond the divergence bounds. The frame's pose is then the initial guess — with
// InitialGuessMode::imu the IMU-propagated pose — flagged `pose_from_gicp = false`, and it
// does not become a keyframe.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "rt/spsc_ring.hpp"

#include "tracking/frame_history.hpp"
#include "tracking/gicp.hpp"
#include "tracking/initial_guess.hpp"
#include "tracking/keyframe_policy.hpp"
#include "tracking/local_map.hpp"
#include "tracking/preprocess.hpp"

namespace vigs::tracking {

enum class TrackingStatus {
  initialized,       ///< first frame: the map starts here
  tracked,           ///< GICP pose accepted
  lost_low_inliers,  ///< inlier ratio below min_inlier_ratio
  lost_diverged,     ///< GICP diverged or moved the guess beyond the bounds
  lost_degenerate,   ///< GICP Hessian degenerate (e.g. a single wall)
};
std::string_view to_string(TrackingStatus status);

struct TrackingOutput {
  std::int64_t t_ns = 0;
  geometry::Pose T_w_c = geometry::Pose::Identity();
  geometry::Pose T_w_c_guess = geometry::Pose::Identity();
  bool pose_from_gicp = false;   ///< false: T_w_c is the (IMU) guess, not a measurement
  bool guess_fell_back = false;  ///< imu mode without an IMU pose: constant velocity used
  bool keyframe = false;
  /// This frame became a held keyframe (moving test on): last_keyframe() carries it, with this
  /// frame's t_ns, on the frame that releases it (keyframe = true) moving_window_frames frames
  /// later. A caller that needs the keyframe's images keeps this frame's until then; held
  /// keyframes are released oldest first, never dropped.
  bool held = false;
  /// The local map was restarted at this frame (reinit_after_lost_frames lost frames in a
  /// row): it is a keyframe at its guess pose, and keyframes still held were dropped.
  bool reinitialized = false;
  TrackingStatus status = TrackingStatus::initialized;
  GicpResult gicp;
  DepthToPointsStats points;
  bool prior_used = false;  ///< GICP had the caller's pose prior (fused tracking)
  bool degenerate = false;  ///< GICP alone left a direction unconstrained (gicp.eigen_ratio)
  /// Information of T_w_c in metric units for xi = [rotation (rad); translation (m)], the left
  /// increment about the world origin (gicp.information / gicp_variance_scale, plus the prior's
  /// when there was one). Zero when the pose is not from GICP.
  Matrix6d information = Matrix6d::Zero();
  /// Points of the keyframe flagged moving (0 for other frames). With the moving test on, the
  /// keyframe (last_keyframe(): its own t_ns and T_w_c) is published moving_window_frames frames
  /// after its own frame, once the frames after it are seen.
  int moving_points = 0;
};

class Tracker {
 public:
  /// preprocess, gicp, local_map, keyframe, initial_guess, min_inlier_ratio, max_correction_*,
  /// gicp_variance_scale, moving_margin_m and moving_window_frames:
  /// config/tracking_components.hpp (the defaults)
  /// and config/tracking_settings.hpp (the robot file's keys and docs).
  struct Setting : config::TrackerSetting {
    int preprocess_threads = gicp.num_threads;
    /// Member 1 of the tracker's worker team (more members: rt::worker_spec). Normal priority
    /// by default; the live pipeline passes the thread table's `tracker_w1` as rt: allows
    /// (pipeline::OdometryOptions::worker).
    rt::ThreadSpec worker{.name = "tracker_w1"};
  };

  Tracker(const PinholeCamera& camera, const Setting& setting,
          const geometry::Pose& T_w_c0 = geometry::Pose::Identity());

  /// Tracks one frame; its stamp is frame.t_ns. `T_w_c_imu` is the IMU-propagated pose for
  /// this frame (nullptr when none); it is used in imu mode only. On the first frame it is the
  /// starting pose if given.
  TrackingOutput track(const RgbdView& frame, const geometry::Pose* T_w_c_imu = nullptr);
  /// Owned images (tools, tests): depth in metres, `rgb` empty or of the same size.
  TrackingOutput track(std::int64_t t_ns, const ImageF32& depth_m, const ImageU8& rgb,
                       const geometry::Pose* T_w_c_imu = nullptr) {
    if (depth_m.empty()) throw std::invalid_argument("depth image is empty");
    return track(rgbd_view(t_ns, depth_m, rgb), T_w_c_imu);
  }

  /// Fused tracking: the next track() adds a Gaussian prior on T_w_c to GICP's least squares,
  /// mean `T_w_c_mean` and metric information `information` (of e = [phi; rho] as in
  /// pose_prior.hpp: rad, m, about the world origin). Used once, by the next track() only.
  /// With a prior, a frame GICP alone finds degenerate is still tracked (the prior holds the
  /// weak directions) and flagged `degenerate`.
  void set_pose_prior(const geometry::Pose& T_w_c_mean, const Matrix6d& information);

  /// The most recent keyframe (camera-frame Gaussians and T_w_c), for the mapper.
  [[nodiscard]] const Keyframe& last_keyframe() const { return keyframe_; }
  /// How many keyframes can be held at once (moving_window_frames + 1 with the moving test on,
  /// 0 without): what a caller keeping held frames' images must have room for.
  [[nodiscard]] std::size_t held_capacity() const { return held_capacity_; }
  [[nodiscard]] const LocalMap& local_map() const { return map_; }
  [[nodiscard]] const Setting& setting() const { return setting_; }
  /// Keyframes whose moving test would have flagged most points (taken as a pose error).
  [[nodiscard]] std::int64_t moving_suspect_keyframes() const {
    return history_.suspect_keyframes();
  }
  /// Preprocessing and GICP run on this one team (GICP shares it when gicp.num_threads equals
  /// preprocess_threads, as settings_from_config makes them).
  [[nodiscard]] const rt::WorkerTeam& team() const { return team_; }

 private:
  geometry::Pose guess(std::int64_t t_ns, const geometry::Pose* T_w_c_imu, bool& fell_back) const;
  /// Copies the frame's cloud into a spare keyframe and queues it in held_ (not yet into the
  /// map).
  void hold_keyframe(std::int64_t t_ns, const geometry::Pose& T_w_c);
  /// Copies the frame's cloud into keyframe_ and inserts it into the local map at once.
  void make_keyframe(std::int64_t t_ns, const geometry::Pose& T_w_c);
  /// The oldest held keyframe, once moving_window_frames frames after it are seen: flags its
  /// moving points, inserts it into the local map and makes it keyframe_. Returns its flags.
  int release_held_keyframe();
  /// Drops every held keyframe (map restarted), their buffers back to spare_.
  void drop_held_keyframes();
  [[nodiscard]] std::size_t held_count() const { return held_ ? held_->size() : 0; }
  [[nodiscard]] bool moving_test_on() const { return setting_.moving_test_on(); }

  Setting setting_;
  rt::WorkerTeam team_;
  FramePreprocessor pre_;
  Gicp gicp_;
  LocalMap map_;
  KeyframePolicy policy_;
  /// Fills source_ with GICP's share of cloud_ (gicp_source_stride); returns the cloud GICP
  /// aligns (cloud_ itself at stride 1).
  const GaussianCloud& gicp_source();

  GaussianCloud cloud_;
  GaussianCloud source_;  ///< points and covariances of cloud_'s GICP subset
  Keyframe keyframe_;     ///< the last keyframe inserted into the map (last_keyframe())
  /// A keyframe waiting for the frames after it, and the frames_ index of its own frame.
  struct HeldKeyframe {
    Keyframe keyframe;
    int frame = 0;
  };
  /// Moving test: keyframes waiting for the frames after them, oldest first; at most
  /// held_capacity_ = moving_window_frames + 1 (a keyframe at most every frame; the ring's own
  /// capacity is that rounded up to a power of two). While they wait, tracking goes on and
  /// further keyframes are held: a quick turn does not leave the map behind the camera. This
  /// thread is both ends of the ring.
  std::optional<rt::SpscRing<HeldKeyframe>> held_;
  std::size_t held_capacity_ = 0;
  /// Keyframes with buffers reserved for a whole frame at construction, moved into held_ when
  /// one is held and back when it is released or dropped: the ring constructs and destroys its
  /// elements, so the buffers travel instead of being allocated per keyframe.
  std::vector<Keyframe> spare_;
  geometry::Pose T_w_newest_kf_ = geometry::Pose::Identity();  ///< held or inserted
  PinholeCamera camera_;
  PosePrior prior_;
  bool prior_pending_ = false;
  FrameHistory history_;  ///< recent frames' depth (moving test)
  int frames_ = 0;
  int lost_in_a_row_ = 0;
  geometry::Pose T_w_last_ = geometry::Pose::Identity();
  geometry::Pose T_w_prev_ = geometry::Pose::Identity();
  std::int64_t t_last_ns_ = 0;
  std::int64_t t_prev_ns_ = 0;
  geometry::Pose T_w_c0_;
};

}  // namespace vigs::tracking
