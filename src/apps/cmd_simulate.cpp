// `vigs simulate`: writes a synthetic uHumans-like RGB-D + IMU + ground-truth recording (MCAP).
#include <signal.h>
#include <sys/resource.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

#include "apps/commands.hpp"
#include "apps/finite_option.hpp"
#include "core/config/default_config.hpp"
#include "core/config/diagnostics.hpp"
#include "core/config/yaml_loader.hpp"
#include "io/io_error.hpp"
#include "io/json_text.hpp"
#include "io/output_guard.hpp"
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

// SIGINT/SIGTERM end the run after the frame being written, so the recording is closed with
// its summary and index under the final name. The handler only stores to lock-free atomics
// (async-signal-safe); SA_RESETHAND makes a second signal act as the default (terminate).
std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free);

extern "C" void on_simulate_stop_signal(int signo) {
  g_signal.store(signo, std::memory_order_relaxed);
  g_stop.store(true, std::memory_order_relaxed);
}

/// Installs the handler for SIGINT and SIGTERM for its lifetime, then restores the old ones.
class StopSignals {
 public:
  StopSignals() {
    struct sigaction sa {};
    sa.sa_handler = on_simulate_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND | SA_RESTART;  // no EINTR in the writer
    ::sigaction(SIGINT, &sa, &old_int_);
    ::sigaction(SIGTERM, &sa, &old_term_);
  }
  ~StopSignals() {
    ::sigaction(SIGINT, &old_int_, nullptr);
    ::sigaction(SIGTERM, &old_term_, nullptr);
  }
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

 private:
  struct sigaction old_int_ {
  }, old_term_{};
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
      ->check(kFiniteNumber & CLI::Range(0.0, 36000.0));
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

      io::refuse_output_over_inputs(a.out, {a.config_file});
      io::refuse_output_over_inputs(a.out + ".partial", {a.config_file});
      sim::Simulator simulator(cfg);
      sim::McapSink sink(a.out, sim::McapSinkOptions::from(cfg));
      int last_report = -1;
      sim::SimStats stats;
      {
        const StopSignals signals;
        stats = simulator.run(
            sink,
            [&](double t, double total) {
              if (a.quiet) return;
              const int step = static_cast<int>(t / 10.0);
              if (step != last_report) {
                last_report = step;
                std::fprintf(stderr, "vigs simulate: %.0f / %.0f s\n", t, total);
              }
            },
            &g_stop);
        sink.close();
      }
      if (stats.stopped) {
        std::fprintf(stderr,
                     "vigs simulate: stopped by %s after %lld frames (%.3f s); %s is complete "
                     "up to there\n",
                     g_signal.load() == SIGINT ? "SIGINT" : "SIGTERM",
                     static_cast<long long>(stats.frames), stats.sequence_s, a.out.c_str());
        exit_code.value = 1;
      }
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
      j["stopped_by_signal"] = stats.stopped
                                   ? io::Json(g_signal.load() == SIGINT ? "SIGINT" : "SIGTERM")
                                   : io::Json(nullptr);
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
