#pragma once
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace vigs::io {

/// One line of a TUM trajectory file: `t tx ty tz qx qy qz qw`.
struct TumPose {
  double t_s = 0;                                           ///< timestamp, s
  Eigen::Vector3d p_w_m = Eigen::Vector3d::Zero();          ///< position in world, m
  Eigen::Quaterniond q_w = Eigen::Quaterniond::Identity();  ///< orientation in world, as read
};

/// Parses TUM text. Empty lines and lines starting with '#' are skipped; fields may be
/// separated by spaces, tabs or commas. A line without exactly 8 finite numbers throws IoError
/// "NAME:LINE: ...". Quaternions are returned as read (not normalised); `name` is only used in
/// messages.
std::vector<TumPose> parse_tum_trajectory(std::string_view text, const std::string& name);

/// Reads a TUM file (see parse_tum_trajectory). Throws IoError naming the path.
std::vector<TumPose> read_tum_trajectory(const std::string& path);

/// Formats poses as TUM text, one line per pose, numbers in shortest round-trip form (reading
/// the text back gives bit-identical doubles).
std::string format_tum_trajectory(std::span<const TumPose> poses);

/// Writes poses atomically (temp file in the same folder, then rename). Throws IoError.
void write_tum_trajectory(const std::string& path, std::span<const TumPose> poses);

}  // namespace vigs::io
