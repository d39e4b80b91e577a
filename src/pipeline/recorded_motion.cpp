#include "pipeline/recorded_motion.hpp"

#include <Eigen/Geometry>
#include <algorithm>

#include "io/finite_check.hpp"
#include "io/io_error.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/typed_io.hpp"

namespace vigs::pipeline {

RecordedMotion read_recorded_motion(const std::string& path, const std::string& imu_topic,
                                    const std::string& pose_topic, bool allow_damaged) {
  RecordedMotion motion;
  io::mcap::McapReaderOptions opt;
  opt.topics = {imu_topic, pose_topic};
  try {
    io::mcap::McapReader reader(path, opt);
    io::mcap::MessageView m;
    io::ros_msgs::Imu imu;
    io::ros_msgs::PoseStamped pose;
    while (reader.next(m)) {
      const std::string record =
          path + ": " + m.channel->topic + " message at byte " + std::to_string(m.record_offset);
      const auto where = [&](const std::string& what) {
        return RecordingError(record + ": " + what);
      };
      try {
        if (m.channel->topic == imu_topic) {
          if (!io::ros_msgs::decode_message(m, imu)) throw where("not sensor_msgs/Imu");
          ImuSample s;
          s.t_ns = imu.header.stamp.to_ns();
          s.gyro_rps[0] = imu.angular_velocity.x;
          s.gyro_rps[1] = imu.angular_velocity.y;
          s.gyro_rps[2] = imu.angular_velocity.z;
          s.accel_mps2[0] = imu.linear_acceleration.x;
          s.accel_mps2[1] = imu.linear_acceleration.y;
          s.accel_mps2[2] = imu.linear_acceleration.z;
          io::require_all_finite(record, "angular_velocity", s.gyro_rps, 3);
          io::require_all_finite(record, "linear_acceleration", s.accel_mps2, 3);
          motion.imu.push_back(s);
        } else {
          if (!io::ros_msgs::decode_message(m, pose)) throw where("not geometry_msgs/PoseStamped");
          const auto& p = pose.pose.position;
          const auto& q = pose.pose.orientation;
          const double v[7] = {p.x, p.y, p.z, q.x, q.y, q.z, q.w};
          io::require_all_finite(record, "pose (position xyz, orientation xyzw)", v, 7);
          const Eigen::Quaterniond quat(q.w, q.x, q.y, q.z);
          if (!(quat.norm() > 0.5 && quat.norm() < 1.5)) throw where("quaternion is not unit");
          StampedPose sp;
          sp.t_ns = pose.header.stamp.to_ns();
          sp.T_w_x = geometry::make_pose(Eigen::Vector3d(p.x, p.y, p.z), quat.normalized());
          motion.body_poses.push_back(sp);
        }
      } catch (const io::ros_msgs::DecodeError& e) {
        throw where(e.what());
      }
    }
    if (allow_damaged) {
      motion.damage = io::mcap::damage_of(reader);
    } else if (!reader.issues().empty()) {
      const io::mcap::ReadIssue& issue = reader.issues().front();
      // The reader's message already names the file and the byte offset.
      throw RecordingError("damaged recording (" + std::string(io::mcap::to_string(issue.kind)) +
                           "): " + issue.message +
                           " (vigs replay --allow-truncated replays the intact part)");
    }
  } catch (const io::IoError& e) {
    const std::string what = e.what();
    throw RecordingError(what.find(path) == std::string::npos ? path + ": " + what : what);
  }
  std::stable_sort(motion.imu.begin(), motion.imu.end(),
                   [](const ImuSample& a, const ImuSample& b) { return a.t_ns < b.t_ns; });
  std::stable_sort(motion.body_poses.begin(), motion.body_poses.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.t_ns < b.t_ns; });
  return motion;
}

std::optional<geometry::Pose> interpolate_pose(const std::vector<StampedPose>& poses,
                                               std::int64_t t_ns, std::int64_t max_gap_ns) {
  const auto after =
      std::lower_bound(poses.begin(), poses.end(), t_ns,
                       [](const StampedPose& p, std::int64_t t) { return p.t_ns < t; });
  if (after == poses.end()) return std::nullopt;
  if (after->t_ns == t_ns) return after->T_w_x;
  if (after == poses.begin()) return std::nullopt;
  const StampedPose& a = *(after - 1);
  const StampedPose& b = *after;
  if (b.t_ns - a.t_ns > max_gap_ns) return std::nullopt;
  const double u = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns);
  return geometry::interpolate(a.T_w_x, b.T_w_x, u);
}

}  // namespace vigs::pipeline
