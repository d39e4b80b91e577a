#include "eval/trajectory_file.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

#include "io/io_error.hpp"
#include "io/tum_trajectory.hpp"

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

namespace {

bool is_sep(char c) {
  return c == ' ' || c == '\t' || c == ',' || c == '\r';
}

/// 1-based numbers of the data lines (not blank, not starting with '#'), in order.
std::vector<int> data_lines(const std::string& text, std::vector<std::string>* lines_out) {
  std::vector<int> out;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::size_t i = 0;
    while (i < line.size() && is_sep(line[i])) ++i;
    if (i == line.size() || line[i] == '#') continue;
    out.push_back(line_no);
    if (lines_out != nullptr) lines_out->push_back(line);
  }
  return out;
}

std::size_t count_fields(const std::string& line) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < line.size();) {
    while (i < line.size() && is_sep(line[i])) ++i;
    if (i >= line.size() || line[i] == '#') break;
    ++n;
    while (i < line.size() && !is_sep(line[i])) ++i;
  }
  return n;
}

/// TUM through the recording layer's reader (io/tum_trajectory.hpp), plus the checks
/// evaluation needs: a usable quaternion and non-decreasing stamps.
void parse_tum(const std::string& text, const std::string& name, const std::vector<int>& lines,
               Trajectory& traj) {
  std::vector<io::TumPose> poses;
  try {
    poses = io::parse_tum_trajectory(text, name);
  } catch (const io::IoError& e) {
    throw TrajectoryFileError(e.what());
  }
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const int line_no = i < lines.size() ? lines[i] : 0;
    const io::TumPose& p = poses[i];
    if (p.q_w.norm() < 1e-6) fail(name, line_no, "quaternion (qx qy qz qw) has zero norm");
    if (i > 0 && p.t_s < poses[i - 1].t_s) fail(name, line_no, "timestamp goes backwards");
    traj.poses.push_back({p.t_s, geometry::make_pose(p.p_w_m, p.q_w)});
  }
}

void parse_kitti(const std::vector<std::string>& text_lines, const std::string& name,
                 const std::vector<int>& lines, Trajectory& traj) {
  for (std::size_t k = 0; k < text_lines.size(); ++k) {
    std::string line = text_lines[k];
    const int line_no = lines[k];
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    const std::vector<double> f = parse_numbers(line, name, line_no);
    if (f.size() != 12) {
      fail(name, line_no,
           "expected 12 fields like the first data line (kitti), got " + std::to_string(f.size()));
    }
    Eigen::Matrix3d R;
    R << f[0], f[1], f[2], f[4], f[5], f[6], f[8], f[9], f[10];
    const double orth = (R * R.transpose() - Eigen::Matrix3d::Identity()).norm();
    if (orth > 1e-3 || R.determinant() < 0.0) {
      fail(name, line_no,
           "the 3x3 block is not a rotation (|R R^T - I| = " + std::to_string(orth) + ")");
    }
    TimedPose p;
    p.t_s = static_cast<double>(traj.poses.size());
    p.T_w_x = geometry::Pose::Identity();
    // Re-orthonormalise: files store rotations rounded to a few digits.
    p.T_w_x.linear() = geometry::normalize_rotation<double>(R);
    p.T_w_x.translation() = Eigen::Vector3d(f[3], f[7], f[11]);
    traj.poses.push_back(p);
  }
}

}  // namespace

Trajectory parse_trajectory_text(const std::string& text, const std::string& name) {
  Trajectory traj;
  traj.source = name;
  std::vector<std::string> text_lines;
  const std::vector<int> lines = data_lines(text, &text_lines);
  if (lines.empty()) throw TrajectoryFileError(name + ": no poses in file");
  const std::size_t n = count_fields(text_lines.front());
  if (n == 8) {
    traj.format = TrajectoryFormat::kTum;
    parse_tum(text, name, lines, traj);
  } else if (n == 12) {
    traj.format = TrajectoryFormat::kKitti;
    parse_kitti(text_lines, name, lines, traj);
  } else {
    fail(name, lines.front(),
         "expected 8 fields (TUM: t tx ty tz qx qy qz qw) or 12 (KITTI 3x4 pose), got " +
             std::to_string(n));
  }
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
