#include "eval/trajectory_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

namespace vigs::eval {
namespace {

[[noreturn]] void fail(const std::string& name, int line, const std::string& what) {
  throw TrajectoryFileError(name + ":" + std::to_string(line) + ": " + what);
}

std::vector<double> parse_numbers(const std::string& line, const std::string& name, int line_no) {
  std::vector<double> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() &&
           (line[i] == ' ' || line[i] == '\t' || line[i] == ',' || line[i] == '\r')) {
      ++i;
    }
    if (i >= line.size()) break;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != ',' &&
           line[j] != '\r') {
      ++j;
    }
    const std::string token = line.substr(i, j - i);
    errno = 0;
    char* end = nullptr;
    const double value = std::strtod(token.c_str(), &end);
    if (end != token.c_str() + token.size() || errno == ERANGE) {
      fail(name, line_no,
           "field " + std::to_string(out.size() + 1) + " '" + token + "' is not a number");
    }
    if (!std::isfinite(value)) {
      fail(name, line_no, "field " + std::to_string(out.size() + 1) + " is not finite");
    }
    out.push_back(value);
    i = j;
  }
  return out;
}

}  // namespace

const char* format_name(TrajectoryFormat f) {
  return f == TrajectoryFormat::kKitti ? "kitti" : "tum";
}

Trajectory parse_trajectory_text(const std::string& text, const std::string& name) {
  Trajectory traj;
  traj.source = name;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  bool format_known = false;
  while (std::getline(in, line)) {
    ++line_no;
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    const std::vector<double> f = parse_numbers(line, name, line_no);
    if (f.empty()) continue;
    if (!format_known) {
      if (f.size() == 8) {
        traj.format = TrajectoryFormat::kTum;
      } else if (f.size() == 12) {
        traj.format = TrajectoryFormat::kKitti;
      } else {
        fail(name, line_no,
             "expected 8 fields (TUM: t tx ty tz qx qy qz qw) or 12 (KITTI 3x4 pose), got " +
                 std::to_string(f.size()));
      }
      format_known = true;
    }
    const std::size_t expected = traj.format == TrajectoryFormat::kTum ? 8 : 12;
    if (f.size() != expected) {
      fail(name, line_no,
           "expected " + std::to_string(expected) + " fields like the first data line (" +
               format_name(traj.format) + "), got " + std::to_string(f.size()));
    }
    TimedPose p;
    if (traj.format == TrajectoryFormat::kTum) {
      p.t_s = f[0];
      const Eigen::Quaterniond q(f[7], f[4], f[5], f[6]);
      const double n = q.norm();
      if (n < 1e-6) fail(name, line_no, "quaternion (qx qy qz qw) has zero norm");
      p.T_w_x = geometry::make_pose(Eigen::Vector3d(f[1], f[2], f[3]), q);
      if (!traj.poses.empty() && p.t_s < traj.poses.back().t_s) {
        fail(name, line_no, "timestamp goes backwards");
      }
    } else {
      p.t_s = static_cast<double>(traj.poses.size());
      Eigen::Matrix3d R;
      R << f[0], f[1], f[2], f[4], f[5], f[6], f[8], f[9], f[10];
      const double orth = (R * R.transpose() - Eigen::Matrix3d::Identity()).norm();
      if (orth > 1e-3 || R.determinant() < 0.0) {
        fail(name, line_no,
             "the 3x3 block is not a rotation (|R R^T - I| = " + std::to_string(orth) + ")");
      }
      p.T_w_x = geometry::Pose::Identity();
      // Re-orthonormalise: files store rotations rounded to a few digits.
      p.T_w_x.linear() = geometry::normalize_rotation<double>(R);
      p.T_w_x.translation() = Eigen::Vector3d(f[3], f[7], f[11]);
    }
    traj.poses.push_back(p);
  }
  if (traj.poses.empty()) throw TrajectoryFileError(name + ": no poses in file");
  return traj;
}

Trajectory load_trajectory_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw TrajectoryFileError(path + ": cannot open trajectory file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_trajectory_text(ss.str(), path);
}

}  // namespace vigs::eval
