// `vigs run`: the live pipeline (pipeline/live_pipeline.hpp) -- sources -> rings -> fixed-rate
// tracker and mapper -> DDS -- and its RESULTS_DIR (trajectory.tum, keyframes.txt, map.ply,
// stats.json, report.md with plots).
//  - no arguments: the main job on the built-in default. A short office sequence (the default
//    robot's 720x480 camera at 20 Hz, IMU at 200 Hz, people walking) is simulated once and
//    cached, then played through the real drivers in real time (pipeline/driver_replay.hpp:
//    an .oni clip through OpenNI2, the IMU as Xsens bytes on a pty) with mapping on and DDS on
//    loopback;
//  - --source replay:F.mcap: that recording, played straight into the rings in real time, or
//    with --through-drivers as the default is; --lockstep: straight into the rings, nothing
//    drops, same result twice;
//  - --source live (with --config ROBOT.yaml): the robot's OpenNI2 camera and serial IMU; the
//    source without --source when the robot's camera.driver is a device (not replay);
//  - --record F.mcap (with the drivers: live, the default, --through-drivers): also record the
//    drivers' taps and the tracker's poses (src/record), F.mcap.partial until a normal stop.
// SIGINT / SIGTERM: the rings are drained and the RESULTS_DIR written whole (report.md and plots
// included, all in one temporary folder swapped into place), exit 0; a second signal exits at
// once, and RESULTS_DIR is then this run's whole folder or what it was before (absent, or an
// earlier run whole), never a part.
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "apps/commands.hpp"
#include "apps/replay_stats.hpp"
#include "core/config/default_config.hpp"
#include "core/config/yaml_loader.hpp"
#include "core/geometry/body_from_camera.hpp"
#include "eval/report.hpp"
#include "io/json_text.hpp"
#include "io/output_guard.hpp"
#include "pipeline/live_pipeline.hpp"
#include "pipeline/progress_line.hpp"
#include "pipeline/results_writer.hpp"
#include "sim/mcap_sink.hpp"
#include "sim/simulator.hpp"

namespace vigs::apps {
namespace {

std::atomic<int> g_run_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);
extern "C" void on_run_stop_signal(int sig) {
  // The first signal asks for a drain-and-save; a second one exits at once.
  if (g_run_signal.exchange(sig, std::memory_order_relaxed) != 0) ::_exit(128 + sig);
}

struct RunArgs {
  std::string source, config_file, out = "results", record;  // source "": from the config
  bool lockstep = false, no_map = false, quiet = false, no_report = false;
  bool through_drivers = false;
  std::int64_t frames = 0;
  double seconds = 10.0;
  int humans = 4;
  int dds_domain = -1;
  int wait_subscribers = 0;
};

/// The default sequence, simulated once into the cache folder ($VIGS_CACHE_DIR, else
/// $XDG_CACHE_HOME/vigs, else ~/.cache/vigs). McapSink writes FILE.partial and renames it, so
/// an interrupted simulation never leaves a cached file.
std::string default_sequence(const config::RobotConfig& base, const RunArgs& a, bool quiet) {
  std::filesystem::path dir;
  if (const char* d = std::getenv("VIGS_CACHE_DIR"); d != nullptr && *d != '\0') {
    dir = d;
  } else if (const char* x = std::getenv("XDG_CACHE_HOME"); x != nullptr && *x != '\0') {
    dir = std::filesystem::path(x) / "vigs";
  } else if (const char* h = std::getenv("HOME"); h != nullptr && *h != '\0') {
    dir = std::filesystem::path(h) / ".cache" / "vigs";
  } else {
    dir = std::filesystem::temp_directory_path() / "vigs-cache";
  }
  std::filesystem::create_directories(dir);
  config::RobotConfig cfg = base;
  cfg.sim.seconds = a.seconds;
  cfg.sim.humans = a.humans;
  const std::string path =
      (dir / ("office_" + std::to_string(cfg.camera.width_px) + "x" +
              std::to_string(cfg.camera.height_px) + "_" + std::to_string(a.humans) + "p_" +
              std::to_string(static_cast<long>(a.seconds * 1000)) + "ms_seed" +
              std::to_string(cfg.sim.seed) + ".mcap"))
          .string();
  if (std::filesystem::exists(path)) return path;
  if (!quiet)
    std::fprintf(stderr,
                 "vigs run: simulating the default office sequence (%.0f s, %d people) "
                 "once -> %s\n",
                 a.seconds, a.humans, path.c_str());
  sim::Simulator simulator(cfg);
  sim::McapSink sink(path, sim::McapSinkOptions::from(cfg));
  const sim::SimStats st = simulator.run(sink, {}, nullptr);
  sink.close();
  (void)st;
  return path;
}

io::Json live_stats(const pipeline::LiveResult& r, const std::string& recording,
                    const std::string& mode) {
  io::Json s = stats_json(r.replay, recording);
  const auto ms = [](std::int64_t ns) { return io::rounded(static_cast<double>(ns) * 1e-6, 10); };
  s["mode"] = mode;
  s["real_time_factor"] = io::rounded(r.real_time_factor, 10);
  s["real_time_factor_steady"] = r.real_time_factor_steady
                                     ? io::Json(io::rounded(*r.real_time_factor_steady, 10))
                                     : io::Json(nullptr);
  s["stream_s"] = io::rounded(r.stream_s, 10);
  s["tracker_cycle_ms_p50"] = ms(r.cycle_p50_ns);
  s["tracker_cycle_ms_p99"] = ms(r.cycle_p99_ns);
  s["tracker_cycles"] = r.tracker_cycles;
  s["tracker_overruns"] = r.tracker_overruns;
  s["tracker_overruns_steady"] =
      r.tracker_overruns_steady ? io::Json(*r.tracker_overruns_steady) : io::Json(nullptr);
  s["tracker_missed_deadlines"] = r.tracker_missed;
  s["tracker_phase_shift_ms"] = ms(static_cast<std::int64_t>(r.tracker_phase_shift_ns));
  s["pose_latency_ms_p50"] = ms(r.pose_latency_ns.p50_ns);
  s["pose_latency_ms_p99"] = ms(r.pose_latency_ns.p99_ns);
  s["frame_wait_ms_p50"] = ms(r.frame_wait_ns.p50_ns);
  s["frame_wait_ms_p99"] = ms(r.frame_wait_ns.p99_ns);
  s["frames_skipped"] = r.tracker.skipped;
  s["frames_out_of_order"] = r.tracker.out_of_order;
  s["frames_waiting_imu"] = r.tracker.waiting_imu;
  s["imu_refused"] = r.tracker.imu_refused;
  s["frames_imu_late"] = r.tracker.imu_late;
  s["keyframes_dropped"] = r.tracker.keyframe_drops;
  s["source_frame_drops"] = r.source.frame_drops;
  s["source_imu_drops"] = r.source.imu_drops;
  s["drops"] = r.drops;
  s["poses_published"] = r.poses_published;
  s["status_published"] = r.status_published;
  s["memory_lock"] = r.memory_lock;
  if (r.tracker_worker) {
    s["tracker_worker"] = io::Json{{"name", std::string(r.tracker_worker->name.view())},
                                   {"cpu", r.tracker_worker->cpu},
                                   {"fifo_priority", r.tracker_worker->sched_fifo_priority},
                                   {"applied", r.tracker_worker_status.describe()}};
  }
  s["stopped_by_signal"] = r.stopped_by_signal;
  if (r.record) {
    const pipeline::LiveRecordResult& rec = *r.record;
    s["record"] = io::Json{{"file", rec.file},
                           {"frames", rec.written.frames},
                           {"imu_samples", rec.written.imu_samples},
                           {"serial_bytes", rec.written.serial_bytes},
                           {"poses", rec.written.poses},
                           {"edges", rec.written.edges},
                           {"bytes", rec.written.bytes_written},
                           {"chunks", rec.written.chunks},
                           {"frame_tap_drops", rec.frame_tap_drops},
                           {"imu_tap_drops", rec.imu_tap_drops},
                           {"serial_tap_drops", rec.serial_tap_drops},
                           {"pose_tap_drops", rec.pose_tap_drops},
                           {"edge_tap_drops", rec.edge_tap_drops},
                           {"tap_drops", rec.tap_drops()}};
  }
  if (r.camera_driver) s["camera_driver"] = drivers::to_json_value(*r.camera_driver);
  if (r.imu_driver) s["imu_driver"] = r.imu_driver->to_json_value();
  if (r.trigger) s["trigger"] = drivers::to_json_value(*r.trigger);
  if (r.trigger_match) s["trigger_match"] = drivers::to_json_value(*r.trigger_match);
  if (mode.find("drivers") != std::string::npos) {
    s["host_minus_recording_ns"] = r.host_minus_recording_ns;
    s["feeder"] = io::Json{{"imu_samples_written", r.feeder.imu_samples_written},
                           {"imu_samples_withheld", r.feeder.imu_samples_withheld},
                           {"imu_messages_corrupted", r.feeder.imu_messages_corrupted},
                           {"late_samples", r.feeder.late_samples},
                           {"camera_returns", r.feeder.camera_returns}};
  }
  return s;
}

int run_command(const RunArgs& a) {
  const bool quiet = a.quiet;
  const config::RobotConfig cfg =
      a.config_file.empty() ? config::load_config_text(config::default_config_text(),
                                                       std::string(config::kDefaultConfigName))
                            : config::load_config_file(a.config_file);
  pipeline::LiveOptions o;
  o.config_path = a.config_file;
  o.lockstep = a.lockstep;
  o.mapping = !a.no_map;
  o.max_frames = a.frames;
  if (a.dds_domain >= 0) o.dds_domain = a.dds_domain;
  o.stop = &g_run_signal;
  o.wait_for_subscribers = a.wait_subscribers;
  std::string mode;
  // Without --source: a robot file whose camera is a device (camera.driver openni2 or v4l2)
  // runs its live sensors; the built-in default and sim robots (driver replay) the default job.
  const std::string source =
      !a.source.empty() ? a.source : (cfg.camera.driver == "replay" ? "default" : "live");
  if (source == "default") {
    o.recording = default_sequence(cfg, a, quiet);
    mode = "default";
    o.through_drivers = !a.lockstep;  // the main job: through the real drivers
  } else if (source.rfind("replay:", 0) == 0) {
    o.recording = source.substr(7);
    if (o.recording.empty()) throw std::runtime_error("--source replay: needs a file");
    mode = "replay";
  } else if (source == "live") {
    mode = "live";
  } else {
    throw std::runtime_error("--source must be default, live or replay:FILE.mcap, not '" + source +
                             "'");
  }
  if (a.through_drivers) {
    if (o.recording.empty()) throw std::runtime_error("--through-drivers needs a recording");
    if (a.lockstep)
      throw std::runtime_error("--through-drivers plays in real time, not --lockstep");
    o.through_drivers = true;
  }
  if (!a.record.empty()) {
    if (a.lockstep)
      throw std::runtime_error(
          "--record records the drivers in real time; --lockstep plays a recording without "
          "them (record with --through-drivers or --source live)");
    if (!o.recording.empty() && !o.through_drivers)
      throw std::runtime_error(
          "--record records the drivers: add --through-drivers to play the recording through "
          "them");
    o.record_path = a.record;
    // No output overwrites an input: not the recording, its clip or the config ...
    std::vector<std::string> inputs{o.recording, a.config_file};
    if (!o.recording.empty())
      inputs.push_back(pipeline::DriverReplay::cached_clip_path(o.recording));
    io::refuse_output_over_inputs(a.record, inputs);
    io::refuse_output_over_inputs(a.record + ".partial", inputs);
    // ... and it does not go inside the RESULTS_DIR, which is replaced whole.
    try {
      io::refuse_output_dir_over_inputs(
          a.out, {std::filesystem::absolute(a.record).parent_path().string()});
    } catch (const std::exception&) {
      throw std::runtime_error("--record " + a.record + " is inside --out " + a.out +
                               ", which is replaced whole at the end");
    }
  }
  if (o.through_drivers) mode += "+drivers";
  if (a.lockstep) mode += "+lockstep";
  io::refuse_output_dir_over_inputs(a.out, {o.recording, a.config_file});
  if (o.through_drivers && o.max_frames == 0 && !quiet &&
      !pipeline::DriverReplay::clip_cached(o.recording))
    std::fprintf(stderr, "vigs run: writing the recording's OpenNI2 clip once -> %s\n",
                 pipeline::DriverReplay::cached_clip_path(o.recording).c_str());

  g_run_signal.store(0);
  struct sigaction sa {};
  sa.sa_handler = on_run_stop_signal;
  sigemptyset(&sa.sa_mask);
  ::sigaction(SIGINT, &sa, nullptr);
  ::sigaction(SIGTERM, &sa, nullptr);

  const bool tty = !quiet && ::isatty(STDERR_FILENO) == 1;
  const auto progress = [tty](const pipeline::LiveProgress& p) {
    if (!tty) return;
    if (p.recording)
      std::fprintf(stderr, "\rrec %.1f MB  rec drops %llu  ", p.record_mb,
                   static_cast<unsigned long long>(p.record_drops));
    else
      std::fputc('\r', stderr);
    // Trailing blanks cover the end of a longer earlier line.
    std::fprintf(stderr, "%s   ", pipeline::format_progress_line(p).c_str());
  };
  const pipeline::LiveResult r = pipeline::run_live(cfg, o, progress);
  if (tty) std::fputc('\n', stderr);
  if (r.replay.frames.empty()) throw std::runtime_error("no frame was tracked");

  const io::Json stats = live_stats(r, o.recording, mode);
  // report.md and its plots go into the temporary folder too, before the one swap: a second
  // signal while the report is drawn leaves RESULTS_DIR as it was (absent, or an earlier run
  // whole), never a new one without its report. A report that fails leaves the rest of the
  // folder (and none of the report), then fails the command as before.
  std::optional<eval::ReportResult> report;
  std::string report_error;
  const auto write_report_into = [&](const std::filesystem::path& tmp) {
    if (o.recording.empty() || a.no_report) return;
    eval::ReportOptions ro;
    ro.results_dir = tmp.string();
    ro.shown_dir = a.out;
    ro.gt_path = o.recording;
    ro.T_b_c = geometry::body_from_camera(cfg.extrinsics);
    ro.render = false;  // PSNR/SSIM renders: `vigs eval run` on the folder
    try {
      report = eval::write_report(ro);
    } catch (const std::exception& e) {
      report_error = e.what();
      std::error_code ec;
      std::filesystem::remove(tmp / "report.md", ec);
      std::filesystem::remove_all(tmp / "plots", ec);
    }
  };
  pipeline::write_results_dir(a.out, r.replay, io::json_lines(stats) + "\n", write_report_into);
  if (!report_error.empty()) throw std::runtime_error("report.md: " + report_error);
  io::Json summary{{"out", a.out},
                   {"mode", mode},
                   {"frames", r.replay.frames.size()},
                   {"real_time_factor", io::rounded(r.real_time_factor, 4)},
                   {"tracker_cycle_ms_p99", io::rounded(r.cycle_p99_ns * 1e-6, 4)},
                   {"track_ms_p99", io::rounded(r.track_p99_ns * 1e-6, 4)},
                   {"pose_latency_ms_p99", io::rounded(r.pose_latency_ns.p99_ns * 1e-6, 4)},
                   {"drops", r.drops}};
  if (r.record) {
    summary["record"] = r.record->file;
    summary["record_tap_drops"] = r.record->tap_drops();
  }
  if (report) {
    for (const auto& w : report->warnings) std::cerr << "vigs run: " << w << "\n";
    summary["ate_rmse_m"] = io::rounded(report->ate.stats.rmse, 4);
  }
  std::printf("%s\n", io::json_line(summary).c_str());
  if (!quiet) {
    std::fprintf(
        stderr,
        "vigs run: %zu frames, real-time factor %.2f, tracker p99 %.1f ms, "
        "drops %llu%s -> %s\n",
        r.replay.frames.size(), r.real_time_factor, r.cycle_p99_ns * 1e-6,
        static_cast<unsigned long long>(r.drops),
        summary.contains("ate_rmse_m")
            ? (", ATE " + std::to_string(summary["ate_rmse_m"].get<double>()) + " m").c_str()
            : "",
        a.out.c_str());
  }
  return 0;
}

}  // namespace

void add_run_command(CLI::App& app, ExitCode& exit_code) {
  auto* cmd = app.add_subcommand(
      "run",
      "The live pipeline: sources -> rings -> tracker and mapper tasks -> DDS; writes a "
      "RESULTS_DIR. Without arguments: a cached simulated office sequence in real time");
  static RunArgs a;
  cmd->add_option("--source", a.source,
                  "default (simulated office, cached), live (the robot's sensors), or "
                  "replay:FILE.mcap; without it: live when --config names a robot whose "
                  "camera.driver is a device (openni2, v4l2), else default");
  cmd->add_option("--config", a.config_file, "robot YAML (default: built-in)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", a.out, "RESULTS_DIR to write (default: results)");
  cmd->add_flag("--lockstep", a.lockstep,
                "each stage waits for the next: nothing drops, two runs give the same "
                "trajectory (needs a recording)");
  cmd->add_flag("--through-drivers", a.through_drivers,
                "replay: play the recording through the real drivers in real time (an .oni "
                "clip through OpenNI2, the IMU as Xsens bytes on a pseudo-terminal), as the "
                "default source always is");
  cmd->add_option("--record", a.record,
                  "also record the drivers (frames, IMU samples, raw serial bytes) and the "
                  "tracker's poses into this MCAP (FILE.partial until a normal stop; needs the "
                  "drivers: live, the default source, --through-drivers)");
  cmd->add_flag("--no-map", a.no_map, "no mapper task");
  cmd->add_option("--frames", a.frames, "recording: only the first N frames (0 = all)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--seconds", a.seconds, "default sequence length, s")
      ->check(CLI::Range(1.0, 600.0));
  cmd->add_option("--humans", a.humans, "default sequence: walking people")
      ->check(CLI::Range(0, 60));
  cmd->add_option("--dds-domain", a.dds_domain, "override dds.domain_id")
      ->check(CLI::Range(0, 232));
  cmd->add_option("--wait-subscribers", a.wait_subscribers,
                  "start the sources once this many pose subscribers matched (30 s at most)")
      ->check(CLI::Range(0, 100));
  cmd->add_flag("--no-report", a.no_report, "skip report.md (ATE, plots)");
  cmd->add_flag("--quiet", a.quiet, "no progress on stderr");
  cmd->callback([&exit_code] {
    try {
      exit_code.value = run_command(a);
    } catch (const std::exception& e) {
      std::cerr << "vigs run: " << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
