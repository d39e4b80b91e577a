#pragma once
// One camera pose estimate as it leaves the tracker: the item of the tracker -> publisher ring
// (DDS pose, odometry, TF and keyframe topics) and of the recorder's pose tap. Plain data, fixed
// size, no allocation, so it can sit in an rt::SpscRing.
#include <cstdint>

namespace vigs {

/// How the pose was obtained. On DDS: PoseQuality.source (src/dds/msg/PoseQuality.msg).
enum class PoseSource : std::uint8_t {
  kTracked = 0,  ///< GICP (fused with the IMU prediction) against the local map
  /// Tracking failed (a lost frame) or no depth: the pose is the tracker's guess, propagated
  /// with the IMU (with a motion model when tracking.initial_guess is not imu).
  kImuPropagated = 1,
  kInitial = 2,      ///< the first frame: the map starts here
  kGroundTruth = 3,  ///< from a simulator or dataset
};

/// Per-sample fault flags (bit mask), so a subscriber sees why a pose is degraded. On DDS:
/// PoseQuality.flags, FLAG_* (src/dds/msg/PoseQuality.msg).
enum PoseFlags : std::uint32_t {
  kPoseFlagNone = 0,
  kPoseFlagDegenerate = 1u << 0,      ///< GICP information matrix has weak directions
  kPoseFlagImuUnavailable = 1u << 1,  ///< no IMU prediction for this frame (stream stopped)
  kPoseFlagFramesSkipped = 1u << 2,   ///< the tracker skipped older frames to reach this one
  kPoseFlagOutOfOrder = 1u << 3,      ///< an out-of-order frame was discarded before this one
  /// The tracker restarted its local map at this frame (tracking.reinit_after_lost_frames lost
  /// frames in a row): poses before and after it are not in one consistent map.
  kPoseFlagMapRestarted = 1u << 4,
  /// The serial IMU driver rejected corrupt bytes (a bad checksum, bytes skipped to resync)
  /// since the previous pose: an IMU sample may be missing before this frame.
  kPoseFlagImuCorrupt = 1u << 5,
  /// The camera stream was lost since the previous pose and this frame is from the reopened
  /// device: a gap in the frames, and the camera's clock anchored again.
  kPoseFlagCameraReopened = 1u << 6,
};

struct PoseSample {
  std::int64_t t_ns = 0;              ///< the frame's sensor stamp (not the publish time), ns
  std::uint64_t frame_index = 0;      ///< 0-based index of the frame in its stream
  double p_w_m[3] = {};               ///< camera position in the world (map) frame, m
  double q_w_xyzw[4] = {0, 0, 0, 1};  ///< camera orientation in the world frame, x y z w
  /// 6x6 row-major covariance of the pose, order [x y z rx ry rz] (ROS 2's
  /// PoseWithCovariance convention), m^2 / rad^2; from the tracker's information matrix.
  double covariance[36] = {};
  double v_w_mps[3] = {};        ///< camera velocity in the world frame (IMU state), m/s
  double omega_c_radps[3] = {};  ///< camera angular rate in the camera frame, rad/s
  PoseSource source = PoseSource::kTracked;
  bool keyframe = false;                ///< this frame became a keyframe
  std::uint32_t flags = kPoseFlagNone;  ///< PoseFlags bits
};

}  // namespace vigs
