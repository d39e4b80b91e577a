#pragma once
// Shared by the pipeline tests and bench_pipeline: a short simulated office sequence at a small
// resolution (240x160, a third of uHumans2's 720x480 with the same 90 deg field of view),
// written to an MCAP file in a private temporary folder, and the ATE of a replay against the
// recording's ground truth.
#include <stdlib.h>

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "../common/scaled_camera.hpp"
#include "core/config/robot_config.hpp"
#include "eval/ate.hpp"
#include "inertial/inertial_frontend.hpp"
#include "pipeline/lockstep_replay.hpp"
#include "pipeline/recorded_motion.hpp"
#include "sim/mcap_sink.hpp"
#include "sim/simulator.hpp"

namespace vigs::pipeline::testing {

/// The office route (2 s at rest, then walking at up to 1.2 m/s) without people, 240x160,
/// tracked with pixel stride 2 (about 9,600 points a frame, as many as stride 4 at 480x320).
inline config::RobotConfig small_office(double seconds) {
  config::RobotConfig cfg;
  vigs::test::use_default_camera_divided(cfg.camera, 3);
  cfg.sim.preset = "office";
  cfg.sim.humans = 0;
  cfg.sim.seconds = seconds;
  cfg.tracking.preprocess.depth.pixel_stride = 2;
  return cfg;
}

/// small_office for the live pipeline's tests: unprivileged (no mlockall, SCHED_FIFO or
/// pinning), DDS off unless a test turns it on, one mapper thread.
inline config::RobotConfig live_test_config(double seconds) {
  config::RobotConfig cfg = small_office(seconds);
  cfg.rt.lock_memory = false;
  cfg.rt.realtime_priorities = false;
  cfg.rt.pin_cpus = false;
  cfg.dds.enabled = false;
  cfg.mapping.threads = 1;
  return cfg;
}

/// A folder made with mkdtemp, removed with its contents on destruction.
class TempDir {
 public:
  TempDir() {
    std::string pattern =
        (std::filesystem::temp_directory_path() / "vigs_pipeline_XXXXXX").string();
    if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] std::string file(const std::string& name) const {
    return (std::filesystem::path(path_) / name).string();
  }

 private:
  std::string path_;
};

/// Simulates `cfg` into `path` (as `vigs simulate` does).
inline void simulate(const config::RobotConfig& cfg, const std::string& path) {
  sim::Simulator simulator(cfg);
  sim::McapSink sink(path, sim::McapSinkOptions::from(cfg));
  simulator.run(sink);
  sink.close();
}

/// Ground-truth camera poses T_w_c = T_w_b T_b_c at the stamps of `frames`.
inline eval::Trajectory ground_truth_camera(const RecordedMotion& motion,
                                            const std::vector<TrackedFrame>& frames,
                                            const config::RobotConfig& cfg) {
  const geometry::Pose T_b_c =
      inertial::InertialFrontendOptions::from(cfg.imu, cfg.extrinsics, cfg.inertial).T_b_c;
  eval::Trajectory gt;
  for (const TrackedFrame& f : frames) {
    const auto T_w_b = interpolate_pose(motion.body_poses, f.t_ns);
    if (!T_w_b) throw std::runtime_error("no ground truth at a frame stamp");
    gt.poses.push_back({static_cast<double>(f.t_ns) * 1e-9, *T_w_b * T_b_c});
  }
  return gt;
}

inline eval::Trajectory estimate(const std::vector<TrackedFrame>& frames) {
  eval::Trajectory est;
  for (const TrackedFrame& f : frames)
    est.poses.push_back({static_cast<double>(f.t_ns) * 1e-9, f.T_w_c});
  return est;
}

/// ATE (SE(3) alignment, true RMSE) of the replayed camera poses.
inline eval::AteResult camera_ate(const RecordedMotion& motion,
                                  const std::vector<TrackedFrame>& frames,
                                  const config::RobotConfig& cfg) {
  return eval::compute_ate(ground_truth_camera(motion, frames, cfg), estimate(frames), {});
}

}  // namespace vigs::pipeline::testing
