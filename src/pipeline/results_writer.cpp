#include "pipeline/results_writer.hpp"

#include <sys/resource.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "io/atomic_dir.hpp"
#include "io/atomic_file.hpp"
#include "io/tum_trajectory.hpp"
#include "mapping/ply_io.hpp"
#include "pipeline/results_dir.hpp"

namespace vigs::pipeline {

double peak_rss_bytes() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) * 1024.0;  // Linux: kilobytes
}

void write_results_dir(const std::string& dir, const ReplayResult& r, const std::string& stats_json,
                       const std::function<void(const std::filesystem::path& tmp)>& also) {
  io::replace_dir_atomically(dir, pipeline::kTrajectoryFile,
                             [&](const std::filesystem::path& root) {
                               write_results_files(root, r, stats_json);
                               if (also) also(root);
                             });
}

void write_results_files(const std::filesystem::path& root, const ReplayResult& r,
                         const std::string& stats_json) {
  std::vector<io::TumPose> poses;
  std::vector<double> keyframe_t_s;
  poses.reserve(r.frames.size());
  for (const TrackedFrame& f : r.frames) {
    io::TumPose p;
    p.t_s = static_cast<double>(f.t_ns) * 1e-9;
    p.p_w_m = f.T_w_c.translation();
    p.q_w = Eigen::Quaterniond(f.T_w_c.linear()).normalized();
    poses.push_back(p);
    if (f.keyframe) keyframe_t_s.push_back(p.t_s);
  }
  io::write_tum_trajectory((root / pipeline::kTrajectoryFile).string(), poses);
  if (!r.frames_odometry.empty()) {
    if (r.frames_odometry.size() != r.frames.size()) {
      throw std::runtime_error("results: " + std::to_string(r.frames_odometry.size()) +
                               " odometry poses for " + std::to_string(r.frames.size()) +
                               " frames");
    }
    for (std::size_t i = 0; i < poses.size(); ++i) {
      poses[i].p_w_m = r.frames_odometry[i].translation();
      poses[i].q_w = Eigen::Quaterniond(r.frames_odometry[i].linear()).normalized();
    }
    io::write_tum_trajectory((root / pipeline::kOdometryTrajectoryFile).string(), poses);
  }

  const auto write_text = [](const std::string& path, const std::string& text) {
    io::write_file_atomically(path, [&](std::FILE* f) {
      if (std::fwrite(text.data(), 1, text.size(), f) != text.size())
        throw std::runtime_error(path + ": write failed");
    });
  };
  write_text(
      (root / pipeline::kKeyframesFile).string(),
      "# keyframe stamps (s) of a vigs replay\n" + pipeline::format_keyframe_times(keyframe_t_s));
  if (r.map) {
    // stats.json is formatted already: a Gaussian the writer had to leave out is said here
    const std::size_t not_finite =
        mapping::write_gaussian_ply((root / pipeline::kMapFile).string(), *r.map);
    if (not_finite > 0)
      std::fprintf(stderr, "vigs: %s: %zu Gaussians with a non-finite parameter left out\n",
                   (root / pipeline::kMapFile).c_str(), not_finite);
  }
  write_text((root / pipeline::kStatsFile).string(), stats_json);
}

}  // namespace vigs::pipeline
