#include "apps/frame_list.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace vigs::apps {

Eigen::Isometry3d pose_from_tum(const double v[7]) {
  for (int i = 0; i < 7; ++i)
    if (!std::isfinite(v[i]))
      throw std::runtime_error("pose number " + std::to_string(i + 1) + " is not finite");
  Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
  if (q.norm() < 1e-6) throw std::runtime_error("pose quaternion has zero length");
  q.normalize();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
  return T;
}

Eigen::Isometry3d parse_pose_text(const std::string& text) {
  std::string s = text;
  for (char& c : s)
    if (c == ',') c = ' ';
  std::istringstream ss(s);
  double v[7];
  for (double& x : v)
    if (!(ss >> x))
      throw std::runtime_error("pose '" + text + "': expected 7 numbers tx ty tz qx qy qz qw");
  std::string extra;
  if (ss >> extra) throw std::runtime_error("pose '" + text + "': more than 7 numbers");
  return pose_from_tum(v);
}

std::vector<PosedFrame> read_frame_list(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error(path + ": cannot open frame list");
  const std::filesystem::path base = std::filesystem::path(path).parent_path();
  std::vector<PosedFrame> frames;
  std::string line;
  int line_no = 0;
  while (std::getline(f, line)) {
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream ss(line);
    PosedFrame fr;
    double v[7];
    if (!(ss >> fr.t_s >> fr.color_path >> fr.depth_path) || !std::isfinite(fr.t_s))
      throw std::runtime_error(path + ":" + std::to_string(line_no) +
                               ": expected 'timestamp colour depth tx ty tz qx qy qz qw'");
    for (double& x : v)
      if (!(ss >> x))
        throw std::runtime_error(path + ":" + std::to_string(line_no) +
                                 ": pose needs 7 numbers tx ty tz qx qy qz qw");
    try {
      fr.T_w_c = pose_from_tum(v);
    } catch (const std::exception& e) {
      throw std::runtime_error(path + ":" + std::to_string(line_no) + ": " + e.what());
    }
    auto resolve = [&](std::string& p) {
      if (!std::filesystem::path(p).is_absolute()) p = (base / p).string();
    };
    resolve(fr.color_path);
    resolve(fr.depth_path);
    frames.push_back(fr);
  }
  if (frames.empty()) throw std::runtime_error(path + ": no frames");
  return frames;
}

}  // namespace vigs::apps
