// `vigs replay`: lockstep replay of an MCAP recording through the odometry (IMU-seeded GICP
// tracking), written as a RESULTS_DIR for `vigs eval run`.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "apps/commands.hpp"
#include "apps/json_text.hpp"
#include "core/config/default_config.hpp"
#include "core/config/diagnostics.hpp"
#include "core/config/yaml_loader.hpp"
#include "pipeline/lockstep_replay.hpp"
#include "pipeline/results_writer.hpp"

namespace vigs::apps {
namespace {

struct ReplayArgs {
  std::string recording, out, config_file, guess, fusion, initial_pose = "gravity";
  std::int64_t frames = 0;
  int map_iterations = 0;
  bool quiet = false;
};

std::string count(long v) {
  return json_number(static_cast<double>(v));
}

/// stats.json: the keys eval::RunStats reads plus the replay's own counters.
std::string stats_json(const pipeline::ReplayResult& r, const std::string& recording) {
  const pipeline::OdometryCounters& c = r.counters;
  const double frames = static_cast<double>(r.frames.size());
  std::string s = "{\n";
  const auto add = [&s](const char* key, const std::string& value) {
    if (s.size() > 2) s += ",\n";
    s += std::string("  \"") + key + "\": " + value;
  };
  add("recording", json_string(recording));
  add("guess", json_string(pipeline::to_string(r.guess)));
  add("fusion",
      json_string(r.guess == tracking::InitialGuessMode::imu ? pipeline::to_string(r.fusion)
                                                             : "none"));
  add("initial_pose", json_string(pipeline::to_string(r.initial_pose)));
  add("frames", json_number(frames));
  add("wall_s", json_number(r.wall_s));
  add("fps", json_number(r.wall_s > 0 ? frames / r.wall_s : NAN));
  add("track_ms_per_frame", json_number(frames > 0 ? 1e3 * r.track_s / frames : NAN));
  add("peak_rss_bytes", json_number(pipeline::peak_rss_bytes()));
  std::vector<float> ms = r.track_ms;
  const auto percentile = [&ms](double q) {
    if (ms.empty()) return static_cast<double>(NAN);
    const auto k = static_cast<std::size_t>(q * static_cast<double>(ms.size() - 1) + 0.5);
    std::nth_element(ms.begin(), ms.begin() + static_cast<std::ptrdiff_t>(k), ms.end());
    return static_cast<double>(ms[k]);
  };
  add("track_ms_p50", json_number(percentile(0.5)));
  add("track_ms_p99", json_number(percentile(0.99)));
  add("tracked", count(c.tracked));
  add("not_converged", count(c.not_converged));
  add("degenerate", count(c.degenerate));
  add("moving_points", count(c.moving_points));
  add("fused_updates", count(c.fused_updates));
  add("lost", count(c.lost));
  add("lost_low_inliers", count(c.lost_low_inliers));
  add("lost_diverged", count(c.lost_diverged));
  add("lost_degenerate", count(c.lost_degenerate));
  add("keyframes", count(c.keyframes));
  add("imu_guesses", count(c.imu_guesses));
  add("imu_unavailable", count(c.imu_unavailable));
  add("imu_resets", count(c.imu_resets));
  add("imu_samples", count(static_cast<long>(r.imu_samples)));
  add("imu_samples_fed", count(static_cast<long>(r.imu_samples_fed)));
  add("frames_without_depth", count(static_cast<long>(r.frames_without_depth)));
  if (r.map) {
    add("gaussians", count(static_cast<long>(r.map->size())));
    add("map_iterations", count(r.map_iterations));
    add("map_ms_per_frame", json_number(frames > 0 ? 1e3 * r.map_s / frames : NAN));
  }
  return s + "\n}\n";
}

}  // namespace

void add_replay_command(CLI::App& app, ExitCode& exit_code) {
  auto* cmd = app.add_subcommand(
      "replay",
      "Replay an MCAP recording in lockstep through IMU-seeded GICP tracking and write a "
      "RESULTS_DIR (trajectory.tum, keyframes.txt, stats.json, optionally map.ply) for "
      "`vigs eval run`");
  static ReplayArgs a;
  cmd->add_option("recording", a.recording, "RGB-D + IMU recording (.mcap, e.g. vigs simulate)")
      ->required();
  cmd->add_option("--out", a.out, "RESULTS_DIR to write (created if missing)")->required();
  cmd->add_option("--config", a.config_file,
                  "robot YAML: tracking, imu, inertial, extrinsics (default: built-in)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--guess", a.guess,
                  "initial guess: imu (VIGS), constant_velocity, previous_pose (GS-ICP SLAM); "
                  "default tracking.initial_guess")
      ->check(CLI::IsMember({"imu", "constant_velocity", "previous_pose"}));
  cmd->add_option("--fusion", a.fusion,
                  "imu guess only: fused (IMU prior in GICP, 15-state filter) or paper (IMU guess, "
                  "then reset from GICP); default tracking.fusion")
      ->check(CLI::IsMember({"fused", "paper"}));
  cmd->add_option("--initial-pose", a.initial_pose,
                  "first pose: gravity (attitude from the accelerometer at rest, yaw 0, the "
                  "default) or ground_truth (the recording's, for debugging)")
      ->check(CLI::IsMember({"gravity", "ground_truth"}));
  cmd->add_option("--frames", a.frames, "replay only the first N frames (0 = all)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--map-iterations", a.map_iterations,
                  "build map.ply: mapper iterations after every frame (0 = no map)")
      ->check(CLI::Range(0, 1000));
  cmd->add_flag("--quiet", a.quiet, "no progress on stderr");
  cmd->callback([&exit_code] {
    try {
      const config::RobotConfig cfg =
          a.config_file.empty() ? config::load_config_text(config::default_config_text(),
                                                           std::string(config::kDefaultConfigName))
                                : config::load_config_file(a.config_file);
      pipeline::ReplayOptions opt;
      if (!a.guess.empty()) opt.guess = tracking::initial_guess_from_string(a.guess);
      if (!a.fusion.empty()) {
        pipeline::FusionMode m = pipeline::FusionMode::fused;
        pipeline::parse_fusion_mode(a.fusion, m);
        opt.fusion = m;
      }
      opt.max_frames = a.frames;
      opt.initial_pose = a.initial_pose == "ground_truth"
                             ? pipeline::InitialPoseSource::ground_truth
                             : pipeline::InitialPoseSource::gravity;
      opt.map_iterations_per_frame = a.map_iterations;
      const auto progress = [](const pipeline::TrackedFrame& f) {
        static long n = 0;
        if (++n % 100 == 0)
          std::fprintf(stderr, "vigs replay: %ld frames, t = %.1f s\n", n,
                       static_cast<double>(f.t_ns) * 1e-9);
      };
      const pipeline::ReplayResult r =
          a.quiet ? pipeline::replay_recording(a.recording, cfg, opt)
                  : pipeline::replay_recording(a.recording, cfg, opt, progress);
      const std::string stats = stats_json(r, a.recording);
      pipeline::write_results_dir(a.out, r, stats);
      std::printf("{\"out\": %s, \"stats\": %s}\n", json_string(a.out).c_str(), stats.c_str());
    } catch (const config::ConfigError& e) {
      std::cerr << "vigs replay: " << e.what() << "\n";
      exit_code.value = 1;
    } catch (const std::exception& e) {
      std::cerr << "vigs replay: " << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
