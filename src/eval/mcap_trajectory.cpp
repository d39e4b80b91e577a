#include "eval/mcap_trajectory.hpp"

#include <algorithm>
#include <cmath>

#include "eval/trajectory_file.hpp"
#include "io/finite_check.hpp"
#include "io/io_error.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/typed_io.hpp"

namespace vigs::eval {

Trajectory load_mcap_trajectory(const std::string& path, const std::string& topic) {
  Trajectory traj;
  traj.source = path;
  traj.format = TrajectoryFormat::kTum;  // stamped poses
  try {
    io::mcap::McapReaderOptions opt;
    opt.topics = {topic};
    io::mcap::McapReader reader(path, opt);
    io::mcap::MessageView m;
    io::ros_msgs::PoseStamped msg;
    while (reader.next(m)) {
      if (!io::ros_msgs::decode_message(m, msg)) {
        throw TrajectoryFileError(path + ": topic " + topic + " at byte " +
                                  std::to_string(m.record_offset) +
                                  " is not geometry_msgs/PoseStamped");
      }
      const auto& p = msg.pose.position;
      const auto& q = msg.pose.orientation;
      const double v[7] = {p.x, p.y, p.z, q.x, q.y, q.z, q.w};
      const std::string record =
          path + ": topic " + topic + " message at byte " + std::to_string(m.record_offset);
      io::require_all_finite(record, "pose (position xyz, orientation xyzw)", v, 7);
      const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
      if (!(norm > 0.5 && norm < 1.5)) {
        throw TrajectoryFileError(record + ": orientation is not a unit quaternion (norm " +
                                  std::to_string(norm) + ")");
      }
      TimedPose tp;
      tp.t_s = static_cast<double>(msg.header.stamp.to_ns()) * 1e-9;
      tp.T_w_x = geometry::make_pose(Eigen::Vector3d(p.x, p.y, p.z),
                                     Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized());
      traj.poses.push_back(tp);
    }
    if (traj.poses.empty()) {
      std::string why = path + ": no PoseStamped messages on topic " + topic;
      if (!reader.issues().empty()) why += " (" + reader.issues().front().message + ")";
      throw TrajectoryFileError(why);
    }
    traj.damage = io::mcap::damage_of(reader);
  } catch (const io::IoError& e) {
    throw TrajectoryFileError(e.what());
  } catch (const io::ros_msgs::DecodeError& e) {
    throw TrajectoryFileError(path + ": " + e.what());
  }
  std::stable_sort(traj.poses.begin(), traj.poses.end(),
                   [](const TimedPose& a, const TimedPose& b) { return a.t_s < b.t_s; });
  return traj;
}

Trajectory load_any_trajectory(const std::string& path, const std::string& mcap_topic) {
  const bool is_mcap = path.size() >= 5 && path.compare(path.size() - 5, 5, ".mcap") == 0;
  return is_mcap ? load_mcap_trajectory(path, mcap_topic) : load_trajectory_file(path);
}

}  // namespace vigs::eval
