// The paper's IMU-vs-no-IMU comparison in one run: the same simulated office sequence replayed
// in lockstep through the odometry with the IMU initial guess (VIGS), previous pose (GS-ICP
// SLAM's baseline) and constant velocity, each reporting ATE (true RMSE, SE(3) alignment) and
// the time per frame.
//
// Sequences (240x160, 90 deg FOV, pixel stride 2, no people, 1.5 m/s cruise speed):
//   range(0) = 20: 20 s with the camera at 20 Hz (up to 7.5 cm between frames);
//   range(0) = 5:  30 s with the camera at 5 Hz (up to 30 cm and ~10 deg between frames: the
//                  frame-to-frame motion of 6 m/s at 20 Hz, i.e. fast motion).
// range(1): 0 imu, 1 previous_pose, 2 constant_velocity. Each replay is deterministic, so one
// iteration is enough; the sequence is simulated once per camera rate (not timed).
//
// BM_TrackOffice720: the tracker alone at 720x480 (lockstep). BM_LiveOffice720: `vigs run`'s
// live pipeline in real time on the same sequence, mapping on, DDS on loopback.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "pipeline/live_pipeline.hpp"
#include "pipeline/lockstep_replay.hpp"
#include "pipeline/replay_figures.hpp"
#include "tests/pipeline/sim_sequence.hpp"

namespace {

using namespace vigs;
using pipeline::testing::TempDir;

struct Sequence {
  config::RobotConfig cfg;
  std::string path;
  pipeline::RecordedMotion motion;
};

const Sequence& sequence(int camera_hz) {
  static TempDir dir;
  static std::map<int, std::unique_ptr<Sequence>> cache;
  auto& s = cache[camera_hz];
  if (!s) {
    s = std::make_unique<Sequence>();
    s->cfg = pipeline::testing::small_office(camera_hz == 20 ? 20.0 : 30.0);
    s->cfg.sim.speed_mps = 1.5;
    s->cfg.camera.rate_hz = camera_hz;
    s->path = dir.file("office_" + std::to_string(camera_hz) + "hz.mcap");
    pipeline::testing::simulate(s->cfg, s->path);
    s->motion = pipeline::read_recorded_motion(s->path);
  }
  return *s;
}

void BM_ReplayOffice(benchmark::State& state) {
  const auto camera_hz = static_cast<int>(state.range(0));
  const tracking::InitialGuessMode modes[] = {tracking::InitialGuessMode::imu,
                                              tracking::InitialGuessMode::previous_pose,
                                              tracking::InitialGuessMode::constant_velocity};
  const tracking::InitialGuessMode mode = modes[state.range(1)];
  const Sequence& seq = sequence(camera_hz);
  pipeline::ReplayOptions opt;
  opt.guess = mode;
  pipeline::ReplayResult r;
  for (auto _ : state) {
    r = pipeline::replay_recording(seq.path, seq.cfg, opt);
    benchmark::DoNotOptimize(r.frames.data());
  }
  const eval::AteResult ate = pipeline::testing::camera_ate(seq.motion, r.frames, seq.cfg);
  const auto frames = static_cast<double>(r.frames.size());
  state.SetLabel(std::string(pipeline::to_string(mode)) + " @ " + std::to_string(camera_hz) +
                 " Hz");
  state.counters["ate_rmse_m"] = ate.stats.rmse;
  state.counters["ate_max_m"] = ate.stats.max;
  state.counters["frames"] = frames;
  state.counters["lost"] = static_cast<double>(r.counters.lost);
  state.counters["track_ms_per_frame"] = 1e3 * r.track_s / frames;
  state.counters["replay_ms_per_frame"] = 1e3 * r.wall_s / frames;
}
BENCHMARK(BM_ReplayOffice)
    ->ArgNames({"camera_hz", "guess"})
    ->ArgsProduct({{20, 5}, {0, 1, 2}})
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kSecond);

// The tracker at the paper's scale: 10 s of the office at 720x480 (pixel stride 4, about
// 21,600 points a frame) with 4 walking people, the IMU guess, no mapping; range(0) is
// tracking.gicp_source_stride (1: GICP aligns every point, the baseline; 2: the default).
// Reports the per-frame tracking time's median and p99 (the goal: 15 / 30 ms on 2
// threads) and the ATE.
/// The 10 s office at 720x480 (the default robot) with 4 walking people, simulated once for the
/// tracker and live benchmarks.
const Sequence& office720() {
  static TempDir dir;
  static const Sequence seq = [] {
    Sequence s;
    s.cfg.sim.preset = "office";
    s.cfg.sim.humans = 4;
    s.cfg.sim.seconds = 10.0;
    s.path = dir.file("office_720x480.mcap");
    pipeline::testing::simulate(s.cfg, s.path);
    s.motion = pipeline::read_recorded_motion(s.path);
    return s;
  }();
  return seq;
}

void BM_TrackOffice720(benchmark::State& state) {
  const Sequence& seq = office720();
  const config::RobotConfig& cfg = seq.cfg;
  const std::string& path = seq.path;
  const pipeline::RecordedMotion& motion = seq.motion;
  config::RobotConfig run = cfg;
  run.tracking.gicp_source_stride = static_cast<int>(state.range(0));
  pipeline::ReplayResult r;
  for (auto _ : state) {
    r = pipeline::replay_recording(path, run, {});
    benchmark::DoNotOptimize(r.frames.data());
  }
  state.counters["track_ms_p50"] = pipeline::track_ms_quantile(r, 0.5).value_or(0.0);
  state.counters["track_ms_p99"] = pipeline::track_ms_quantile(r, 0.99).value_or(0.0);
  state.counters["gicp_iterations"] = pipeline::mean_gicp_iterations(r).value_or(0.0);
  state.counters["ate_rmse_m"] = pipeline::testing::camera_ate(motion, r.frames, run).stats.rmse;
  state.counters["frames"] = static_cast<double>(r.frames.size());
}
BENCHMARK(BM_TrackOffice720)
    ->ArgName("gicp_source_stride")
    ->Arg(1)
    ->Arg(2)
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kSecond);

// The live pipeline in real time, as `vigs run` runs it (the robot file's rt:, mapping on, DDS
// on loopback, domain 231): the 10 s office at 720x480 with 4 people, played straight into the
// rings (range(0) = 0, the baseline) or through the real drivers (1: an .oni clip through
// OpenNI2, the IMU as Xsens bytes on a pseudo-terminal). Issue #14's figures: the real-time
// factor between 10 % and 90 % of the run (goal >= 1.0) and tracker overruns, the tracker's
// cycle p50 / p99 (goal 15 / 30 ms), and the pose latency from a frame's arrival to its pose in
// the publisher's ring (DDS adds its transport: bench_dds, `vigs echo --receipt`).
void BM_LiveOffice720(benchmark::State& state) {
  const Sequence& seq = office720();
  const config::RobotConfig& cfg = seq.cfg;
  const std::string& path = seq.path;
  const pipeline::RecordedMotion& motion = seq.motion;
  pipeline::LiveOptions o;
  o.recording = path;
  o.through_drivers = state.range(0) != 0;
  o.dds_domain = 231;
  pipeline::LiveResult r;
  for (auto _ : state) {
    r = pipeline::run_live(cfg, o);
    benchmark::DoNotOptimize(r.replay.frames.data());
  }
  const auto ms = [](std::int64_t ns) { return static_cast<double>(ns) * 1e-6; };
  state.counters["real_time_factor_steady"] = r.real_time_factor_steady.value_or(0.0);
  state.counters["tracker_overruns"] = static_cast<double>(r.tracker_overruns);
  state.counters["tracker_overruns_steady"] =
      static_cast<double>(r.tracker_overruns_steady.value_or(r.tracker_overruns));
  state.counters["cycle_ms_p50"] = ms(r.cycle_p50_ns);
  state.counters["cycle_ms_p99"] = ms(r.cycle_p99_ns);
  state.counters["pose_latency_ms_p50"] = ms(r.pose_latency_ns.p50_ns);
  state.counters["pose_latency_ms_p99"] = ms(r.pose_latency_ns.p99_ns);
  state.counters["frames_tracked"] = static_cast<double>(r.replay.frames.size());
  state.counters["frames_skipped"] = static_cast<double>(r.tracker.skipped);
  state.counters["poses_published"] = static_cast<double>(r.poses_published);
  state.counters["lost"] = static_cast<double>(r.replay.counters.lost);
  state.counters["ate_rmse_m"] =
      pipeline::testing::camera_ate(motion, r.replay.frames, cfg).stats.rmse;
}
BENCHMARK(BM_LiveOffice720)
    ->ArgName("through_drivers")
    ->Arg(0)
    ->Arg(1)
    ->Iterations(1)
    ->UseRealTime()
    ->Unit(benchmark::kSecond);

}  // namespace

BENCHMARK_MAIN();
