#pragma once
// The motion streams of a recording, read whole before a replay: every sensor_msgs/Imu on the
// IMU topic as ImuSample (header stamp, body-frame rates and specific force) and every
// geometry_msgs/PoseStamped on the ground-truth topic (T_w_b). Both are sorted by stamp, so a
// recording whose messages are out of file order still replays in time order.
//
// 200 Hz IMU is about 11 MB per hour as ImuSample, so holding it is cheap next to the images.
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry/se3.hpp"
#include "core/types/imu_sample.hpp"
#include "io/mcap/damage_report.hpp"
#include "io/recording_topics.hpp"

namespace vigs::pipeline {

/// A recording that cannot be replayed: unreadable, damaged, or a message of the wrong type.
/// The message names the file (and the byte offset where one applies).
class RecordingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct StampedPose {
  std::int64_t t_ns = 0;
  geometry::Pose T_w_x = geometry::Pose::Identity();
};

struct RecordedMotion {
  std::vector<ImuSample> imu;           ///< sorted by t_ns
  std::vector<StampedPose> body_poses;  ///< T_w_b, sorted by t_ns; empty without ground truth
  io::mcap::DamageReport damage;        ///< set only when read with allow_damaged
};

/// Reads the whole file. Throws RecordingError naming the file when it cannot be opened, when
/// the reader found any damage (truncation, bad CRC, malformed record: a partial recording is
/// refused rather than replayed short) unless `allow_damaged` (then the intact part is returned
/// and the damage is in RecordedMotion::damage), when a message on either topic does not
/// decode, or when a number in one is not finite (the record and field are named).
/// A missing topic is not an error: the vector stays empty.
RecordedMotion read_recorded_motion(
    const std::string& path, const std::string& imu_topic = std::string(io::topics::kImu.name),
    const std::string& pose_topic = std::string(io::topics::kBodyPose.name),
    bool allow_damaged = false);

/// T_w_x at t_ns, interpolated between the two poses around it (position linearly, rotation by
/// slerp); nullopt outside [first, last] stamp or when the gap between them exceeds max_gap_ns.
/// The default gap: ground truth at 20 Hz or faster is interpolated, a dropout is not.
inline constexpr std::int64_t kMaxPoseGapNs = 50'000'000;
std::optional<geometry::Pose> interpolate_pose(const std::vector<StampedPose>& poses,
                                               std::int64_t t_ns,
                                               std::int64_t max_gap_ns = kMaxPoseGapNs);

}  // namespace vigs::pipeline
