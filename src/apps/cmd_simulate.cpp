// `vigs simulate`: writes a synthetic uHumans-like RGB-D + IMU + ground-truth recording (MCAP).
#include <sys/resource.h>

#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

#include "apps/commands.hpp"
#include "core/config/default_config.hpp"
#include "core/config/diagnostics.hpp"
#include "core/config/yaml_loader.hpp"
#include "io/io_error.hpp"
#include "io/json_text.hpp"
#include "sim/mcap_sink.hpp"
#include "sim/simulator.hpp"

namespace vigs::apps {
namespace {

struct SimulateArgs {
  std::string out, config_file, preset, depth_encoding;
  std::optional<int> humans, seed, threads;
  std::optional<double> seconds;
  bool gray = false, quiet = false;
};

}  // namespace

void add_simulate_command(CLI::App& app, ExitCode& exit_code) {
  auto* cmd = app.add_subcommand(
      "simulate",
      "Write a synthetic office/apartment sequence (RGB-D 20 Hz, IMU and ground truth 200 Hz) "
      "to one MCAP file");
  static SimulateArgs a;
  cmd->add_option("--out", a.out, "output .mcap file (written as FILE.partial, then renamed)")
      ->required();
  cmd->add_option("--preset", a.preset, "office (64 m x 64 m) | apartment (24 m x 24 m)")
      ->check(CLI::IsMember({"office", "apartment"}));
  cmd->add_option("--humans", a.humans, "walking people (uHumans: 0, 12, 24, 60)")
      ->check(CLI::Range(0, 500));
  cmd->add_option("--seconds", a.seconds, "sequence length, s; 0 = the whole route")
      ->check(CLI::Range(0.0, 36000.0));
  cmd->add_option("--seed", a.seed, "random seed: layout, people, noise")
      ->check(CLI::Range(0, 2147483647));
  cmd->add_flag("--gray", a.gray, "mono8 images (as uHumansV1) instead of rgb8");
  cmd->add_option("--depth-encoding", a.depth_encoding, "16UC1 (mm) | 32FC1 (m)")
      ->check(CLI::IsMember({"16UC1", "32FC1"}));
  cmd->add_option("--threads", a.threads, "ray-casting threads")->check(CLI::Range(1, 64));
  cmd->add_option("--config", a.config_file,
                  "robot YAML: camera, imu, extrinsics and sim sections (default: built-in)")
      ->check(CLI::ExistingFile);
  cmd->add_flag("--quiet", a.quiet, "no progress on stderr");
  cmd->callback([&exit_code] {
    try {
      auto cfg = a.config_file.empty()
                     ? config::load_config_text(config::default_config_text(),
                                                std::string(config::kDefaultConfigName))
                     : config::load_config_file(a.config_file);
      if (!a.preset.empty()) cfg.sim.preset = a.preset;
      if (a.humans) cfg.sim.humans = *a.humans;
      if (a.seconds) cfg.sim.seconds = *a.seconds;
      if (a.seed) cfg.sim.seed = *a.seed;
      if (a.gray) cfg.sim.gray = true;
      if (!a.depth_encoding.empty()) cfg.sim.depth_encoding = a.depth_encoding;
      if (a.threads) cfg.sim.render_threads = *a.threads;

      sim::Simulator simulator(cfg);
      sim::McapSinkOptions opt;
      opt.depth_encoding = cfg.sim.depth_encoding;
      opt.depth_scale_m = cfg.camera.depth_scale_m;
      opt.imu = cfg.imu;
      sim::McapSink sink(a.out, opt);
      int last_report = -1;
      const auto stats = simulator.run(sink, [&](double t, double total) {
        if (a.quiet) return;
        const int step = static_cast<int>(t / 10.0);
        if (step != last_report) {
          last_report = step;
          std::fprintf(stderr, "vigs simulate: %.0f / %.0f s\n", t, total);
        }
      });
      sink.close();
      rusage ru{};
      getrusage(RUSAGE_SELF, &ru);
      const double cpu_s = static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
                           1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
      io::Json j;
      j["out"] = a.out;
      j["preset"] = cfg.sim.preset;
      j["humans"] = cfg.sim.humans;
      j["seed"] = cfg.sim.seed;
      j["gray"] = cfg.sim.gray;
      j["frames"] = stats.frames;
      j["imu_samples"] = stats.imu_samples;
      j["sequence_s"] = io::fixed(stats.sequence_s, 3);
      j["route_length_m"] = io::fixed(stats.route_length_m, 1);
      j["sequence_length_m"] = io::fixed(stats.sequence_length_m, 1);
      j["wall_s"] = io::fixed(stats.wall_s, 3);
      j["render_s"] = io::fixed(stats.render_s, 3);
      j["wall_per_sequence_s"] = io::fixed(stats.wall_s / std::max(stats.sequence_s, 1e-9), 3);
      j["cpu_s"] = io::fixed(cpu_s, 3);
      j["messages"] = sink.stats().message_count;
      j["bytes"] = sink.stats().bytes_written;
      std::printf("%s\n", io::json_line(j).c_str());
    } catch (const config::ConfigError& e) {
      std::cerr << "vigs simulate: " << e.what() << "\n";
      exit_code.value = 1;
    } catch (const std::exception& e) {
      std::cerr << "vigs simulate: " << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
