#pragma once
// A trajectory as evaluation sees it: poses T_w_x (x = body or camera, as the file says)
// stamped in seconds, in file order.
#include <string>
#include <vector>

#include "core/geometry/se3.hpp"

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
};

}  // namespace vigs::eval
