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
#include "apps/replay_stats.hpp"
#include "core/config/default_config.hpp"
#include "core/config/diagnostics.hpp"
#include "core/config/yaml_loader.hpp"
#include "io/json_text.hpp"
#include "io/mcap/damage_object.hpp"
#include "io/output_guard.hpp"
#include "pipeline/lockstep_replay.hpp"
#include "pipeline/results_writer.hpp"

namespace vigs::apps {
namespace {

struct ReplayArgs {
  std::string recording, out, config_file, guess, fusion, initial_pose = "gravity",
                                                          map_poses = "estimate";
  std::int64_t frames = 0, skip_frames = 0;
  int map_iterations = 0;
  double map_budget_ms = 0.0;
  bool quiet = false, allow_truncated = false, as_run = false;
};

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
  cmd->add_option("--skip-frames", a.skip_frames,
                  "start N frames late: the first N frames are not tracked and their IMU samples "
                  "go in before the first tracked frame, as when a live tracker starts late")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--map-iterations", a.map_iterations,
                  "build map.ply: mapper iterations after every frame (0 = no map)")
      ->check(CLI::Range(0, 1000));
  cmd->add_option("--map-budget-ms", a.map_budget_ms,
                  "build map.ply with this mapper time budget per frame, ms (mapping.budget_ms; "
                  "replaces --map-iterations; iteration count follows the wall clock)")
      ->check(CLI::Range(0.0, 10000.0));
  cmd->add_option("--map-poses", a.map_poses,
                  "with a map: keyframes go into it at the tracker's estimate (the default) or at "
                  "the recording's ground-truth poses (the mapper alone, without tracking error; "
                  "`vigs eval run` then renders at the ground truth)")
      ->check(CLI::IsMember({"estimate", "ground_truth"}));
  cmd->add_flag("--allow-truncated", a.allow_truncated,
                "replay the intact part of a damaged (truncated, corrupt) recording instead of "
                "refusing it; stderr and stats.json input_damage say what was used");
  cmd->add_flag("--as-run", a.as_run,
                "track only the frames the recording's run tracked (its /vigs/pose, written by "
                "`vigs run --record`): gives that run's trajectory bit for bit");
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
      if (!a.fusion.empty()) {
        pipeline::FusionMode m = pipeline::FusionMode::fused;
        pipeline::parse_fusion_mode(a.fusion, m);
        opt.fusion = m;
      }
      opt.max_frames = a.frames;
      opt.skip_frames = a.skip_frames;
      opt.initial_pose = a.initial_pose == "ground_truth"
                             ? pipeline::InitialPoseSource::ground_truth
                             : pipeline::InitialPoseSource::gravity;
      opt.map_iterations_per_frame = a.map_iterations;
      opt.map_budget_ms = a.map_budget_ms;
      opt.map_poses = a.map_poses == "ground_truth" ? pipeline::MapPoseSource::ground_truth
                                                    : pipeline::MapPoseSource::estimate;
      opt.allow_damaged = a.allow_truncated;
      opt.as_run = a.as_run;
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
      const io::Json stats = stats_json(r, a.recording);
      pipeline::write_results_dir(a.out, r, io::json_lines(stats) + "\n");
      std::printf("%s\n", io::json_line({{"out", a.out}, {"stats", stats}}).c_str());
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
