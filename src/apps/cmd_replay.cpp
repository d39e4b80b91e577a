// `vigs replay`: lockstep replay of an MCAP recording through the odometry (IMU-seeded GICP
// tracking), written as a RESULTS_DIR for `vigs eval run`.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

#include "apps/commands.hpp"
#include "apps/json_text.hpp"
#include "core/config/default_config.hpp"
#include "core/config/diagnostics.hpp"
#include "core/config/yaml_loader.hpp"
#include "io/output_guard.hpp"
#include "pipeline/lockstep_replay.hpp"
#include "pipeline/results_writer.hpp"

namespace vigs::apps {
namespace {

struct ReplayArgs {
  std::string recording, out, config_file, guess;
  std::int64_t frames = 0;
  int map_iterations = 0;
  bool quiet = false, allow_truncated = false;
};

/// What a replay of a damaged recording used, for stderr and stats.json.
std::string used_of(const pipeline::ReplayResult& r) {
  return std::to_string(r.frames.size()) + " frames" +
         (r.frames.empty() ? std::string()
                           : " up to t = " + std::to_string(r.frames.back().t_ns * 1e-9) + " s") +
         " and " + std::to_string(r.imu_samples) + " IMU samples";
}

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
  add("initial_pose", json_string(pipeline::to_string(r.initial_pose)));
  add("frames", json_number(frames));
  add("wall_s", json_number(r.wall_s));
  add("fps", json_number(r.wall_s > 0 ? frames / r.wall_s : NAN));
  add("track_ms_per_frame", json_number(frames > 0 ? 1e3 * r.track_s / frames : NAN));
  add("peak_rss_bytes", json_number(pipeline::peak_rss_bytes()));
  add("tracked", count(c.tracked));
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
  add("input_damage", io::mcap::damage_json(r.damage, used_of(r)));
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
  cmd->add_option("--frames", a.frames, "replay only the first N frames (0 = all)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--map-iterations", a.map_iterations,
                  "build map.ply: mapper iterations after every frame (0 = no map)")
      ->check(CLI::Range(0, 1000));
  cmd->add_flag("--allow-truncated", a.allow_truncated,
                "replay the intact part of a damaged (truncated, corrupt) recording instead of "
                "refusing it; stderr and stats.json input_damage say what was used");
  cmd->add_flag("--quiet", a.quiet, "no progress on stderr");
  cmd->callback([&exit_code] {
    try {
      io::refuse_output_dir_over_inputs(a.out, {a.recording, a.config_file});
      const config::RobotConfig cfg =
          a.config_file.empty() ? config::load_config_text(config::default_config_text(),
                                                           std::string(config::kDefaultConfigName))
                                : config::load_config_file(a.config_file);
      pipeline::ReplayOptions opt;
      if (!a.guess.empty()) opt.guess = tracking::initial_guess_from_string(a.guess);
      opt.max_frames = a.frames;
      opt.map_iterations_per_frame = a.map_iterations;
      opt.allow_damaged = a.allow_truncated;
      const auto progress = [](const pipeline::TrackedFrame& f) {
        static long n = 0;
        if (++n % 100 == 0)
          std::fprintf(stderr, "vigs replay: %ld frames, t = %.1f s\n", n,
                       static_cast<double>(f.t_ns) * 1e-9);
      };
      const pipeline::ReplayResult r =
          a.quiet ? pipeline::replay_recording(a.recording, cfg, opt)
                  : pipeline::replay_recording(a.recording, cfg, opt, progress);
      if (r.damage.damaged())
        std::cerr << "vigs replay: " << io::mcap::damage_warning(r.damage, used_of(r)) << "\n";
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
