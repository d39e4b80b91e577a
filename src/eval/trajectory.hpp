#pragma once
// A trajectory as evaluation sees it: poses T_w_x (x = body or camera, as the file says)
// stamped in seconds, in file order.
#include <string>
#include <vector>

#include "core/geometry/se3.hpp"
#include "io/mcap/damage_report.hpp"

namespace vigs::eval {

struct TimedPose {
  double t_s = 0.0;      ///< timestamp, s (KITTI files: the pose's line index)
  geometry::Pose T_w_x;  ///< pose in the trajectory's world frame
};

/// How a trajectory file was laid out.
enum class TrajectoryFormat {
  kTum,    ///< `t tx ty tz qx qy qz qw` per line
  kKitti,  ///< 12 numbers per line: the top 3x4 rows of T_w_x, row-major, no timestamp
};

struct Trajectory {
  std::string source;  ///< file name (for messages)
  TrajectoryFormat format = TrajectoryFormat::kTum;
  std::vector<TimedPose> poses;
  /// Damage the reader found in a recording (.mcap); `poses` are those of the intact part.
  io::mcap::DamageReport damage;
};

/// "N poses up to t = T s": what a tool used of a trajectory, for damage reports.
inline std::string poses_used(const Trajectory& t) {
  return std::to_string(t.poses.size()) + " poses" +
         (t.poses.empty() ? std::string()
                          : " up to t = " + std::to_string(t.poses.back().t_s) + " s") +
         " of " + t.source;
}

}  // namespace vigs::eval
