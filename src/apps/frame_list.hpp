#pragma once
// Posed RGB-D frame lists for `vigs map`: one frame per line,
//   timestamp colour_path depth_path tx ty tz qx qy qz qw
// with the pose camera-to-world (T_w_c, metres, Hamilton quaternion). Blank lines and lines
// starting with '#' are skipped; relative paths are relative to the list file's folder.
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace vigs::apps {

struct PosedFrame {
  double t_s = 0;
  std::string color_path;
  std::string depth_path;
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
};

/// Throws std::runtime_error naming the file and line on malformed input.
std::vector<PosedFrame> read_frame_list(const std::string& path);

/// tx ty tz qx qy qz qw -> T_w_c; the quaternion is normalised (error when its norm < 1e-6).
Eigen::Isometry3d pose_from_tum(const double v[7]);

/// Parses "tx ty tz qx qy qz qw" (spaces or commas).
Eigen::Isometry3d parse_pose_text(const std::string& text);

}  // namespace vigs::apps
