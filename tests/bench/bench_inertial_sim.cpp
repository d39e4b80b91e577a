// Drift with and without the gyro-bias estimate on the project simulator (src/sim): the
// simulator's office route (B-spline trajectory), its IMU synthesizer (white noise and bias
// random walk at the built-in configuration's densities) plus a constant turn-on gyro bias
// (the EuRoC V1_02 value; the synthesizer's biases start at zero), and the simulator's
// ground-truth camera poses at the camera rate with independent per-frame noise standing in
// for GICP. Same counters as BM_GyroBiasDrift (bench_inertial_drift.cpp).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/config/default_config.hpp"
#include "core/config/yaml_loader.hpp"
#include "core/geometry/se3.hpp"
#include "inertial/inertial_frontend.hpp"
#include "sim/imu_synth.hpp"
#include "sim/simulator.hpp"
#include "tests/bench/drift_stats.hpp"

namespace {

using Eigen::Vector3d;
using vigs::ImuSample;
using vigs::geometry::Pose;
using namespace vigs::inertial;

// range(0): estimate off/on; range(1): GICP rotation noise, mdeg; range(2): position noise, mm.
void BM_GyroBiasDriftSimulator(benchmark::State& state) {
  const bool estimate = state.range(0) != 0;
  const double rot_noise_rad = 1e-3 * static_cast<double>(state.range(1)) * M_PI / 180.0;
  const double pos_noise_m = 1e-3 * static_cast<double>(state.range(2));
  auto cfg = vigs::config::load_config_text(vigs::config::default_config_text(),
                                            std::string(vigs::config::kDefaultConfigName));
  cfg.sim.seconds = 60.0;
  cfg.sim.humans = 0;  // people only affect images
  cfg.inertial.estimate_gyro_bias = estimate;
  const vigs::sim::Simulator sim(cfg);
  const auto opts = InertialFrontendOptions::from(cfg.imu, cfg.extrinsics, cfg.inertial);

  // IMU at its rate over the sequence, with the true bias per sample.
  const Vector3d turn_on_bias(-0.002153, 0.020744, 0.075806);
  vigs::sim::ImuSynthesizer synth(cfg.imu, 42);
  std::vector<ImuSample> imu;
  std::vector<Vector3d> true_bias;
  const auto imu_period_ns = static_cast<std::int64_t>(std::llround(1e9 / cfg.imu.rate_hz));
  const auto end_ns = static_cast<std::int64_t>(sim.duration_s() * 1e9);
  for (std::int64_t t = 0; t <= end_ns; t += imu_period_ns) {
    true_bias.push_back(synth.gyro_bias() + turn_on_bias);
    ImuSample s = synth.measure(sim.trajectory().state(1e-9 * static_cast<double>(t)), t);
    for (int k = 0; k < 3; ++k) s.gyro_rps[k] += turn_on_bias[k];
    imu.push_back(s);
  }
  const auto frame_ns = static_cast<std::int64_t>(std::llround(1e9 / cfg.camera.rate_hz));
  const double warmup_s = 5.0;
  vigs::bench::DriftStats stats;
  for (auto _ : state) {
    std::mt19937 rng(7);
    std::normal_distribution<double> n01(0.0, 1.0);
    InertialFrontend f(opts);
    std::size_t next = 0;
    auto feed = [&](InertialFrontend& fe, std::size_t& idx, std::int64_t t_ns) {
      while (idx < imu.size() && imu[idx].t_ns <= t_ns + 2 * imu_period_ns) {
        fe.add_sample(imu[idx++]);
      }
    };
    std::int64_t frame = 0;
    for (std::int64_t t = 1'000'000; t + 1'000'000'000 < end_ns; t += frame_ns, ++frame) {
      feed(f, next, t);
      const auto guess = f.predict_camera_pose(t);
      const Pose truth = sim.camera_pose(1e-9 * static_cast<double>(t));
      const bool scored = t > static_cast<std::int64_t>(warmup_s * 1e9);
      if (guess && scored) {
        const auto e = vigs::geometry::pose_error(*guess, truth);
        stats.add_guess(e);
        stats.add_bias_error_sq(
            (f.bias_gyro_rps() - true_bias[static_cast<std::size_t>(t / imu_period_ns)])
                .squaredNorm());
      }
      Pose tracked = truth;
      tracked.linear() = truth.linear() * vigs::geometry::so3_exp<double>(Vector3d(
                                              rot_noise_rad * n01(rng), rot_noise_rad * n01(rng),
                                              rot_noise_rad * n01(rng)));
      tracked.translation() += pos_noise_m * Vector3d(n01(rng), n01(rng), n01(rng));
      f.reset_from_tracked(t, tracked);
      if (scored && frame % 40 == 0) {  // a 1 s tracking outage every 40 frames
        InertialFrontend outage = f;
        std::size_t idx = next;
        const std::int64_t t_end = t + 1'000'000'000;
        feed(outage, idx, t_end);
        if (const auto p = outage.predict_camera_pose(t_end)) {
          const auto e =
              vigs::geometry::pose_error(*p, sim.camera_pose(1e-9 * static_cast<double>(t_end)));
          stats.add_drift(e);
        }
      }
    }
  }
  stats.report(state, /*guess_position=*/true, /*bias=*/true);
  state.SetLabel(estimate ? "gyro-bias estimate on" : "off (baseline)");
}
BENCHMARK(BM_GyroBiasDriftSimulator)
    ->ArgNames({"estimate", "rot_mdeg", "pos_mm"})
    ->Args({0, 20, 2})
    ->Args({1, 20, 2})
    ->Args({0, 50, 5})
    ->Args({1, 50, 5})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
