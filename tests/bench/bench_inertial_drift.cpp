// Drift with and without the gyro-bias estimate (inertial/gyro_bias_estimator.hpp), on an
// analytic synthetic trajectory (inertial/synthetic_motion.hpp): 60 s, IMU at 200 Hz with
// white noise and bias random walk at the built-in configuration's densities, starting from
// the EuRoC V1_02 ground-truth biases; camera at 20 Hz whose "GICP" poses are the truth
// perturbed by independent per-frame noise. Counters (deterministic, fixed seeds):
//   guess_rot_rms_deg / guess_pos_rms_m   initial-guess error per frame (after 5 s warm-up)
//   drift1s_rot_rms_deg / drift1s_pos_rms_m  IMU-only dead reckoning over a 1 s tracking
//                                         outage, started every 2 s after warm-up
//   bias_err_rms_rps                      |bg_est - bg_true| over frames after warm-up
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/config/extrinsics_settings.hpp"
#include "core/config/imu_settings.hpp"
#include "core/config/inertial_settings.hpp"
#include "core/geometry/se3.hpp"
#include "inertial/euroc_csv.hpp"
#include "inertial/inertial_frontend.hpp"
#include "inertial/synthetic_motion.hpp"
#include "tests/bench/drift_stats.hpp"

namespace {

using Eigen::Vector3d;
using vigs::ImuSample;
using vigs::geometry::Pose;
using namespace vigs::inertial;

struct SimImu {
  std::vector<ImuSample> samples;
  std::vector<Vector3d> gyro_bias;  // true bias per sample
};

SimImu simulate_imu(const SyntheticMotion& motion, const vigs::config::ImuSettings& imu,
                    double duration_s, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  const double dt = 1.0 / imu.rate_hz;
  const auto period_ns = static_cast<std::int64_t>(std::llround(1e9 * dt));
  Vector3d bg(-0.002153, 0.020744, 0.075806), ba(-0.013337, 0.103464, 0.093086);
  SimImu out;
  const Vector3d g(0, 0, -imu.gravity_mps2);
  for (std::int64_t t = 0; t <= static_cast<std::int64_t>(duration_s * 1e9); t += period_ns) {
    ImuSample s = motion.sample(t, g);
    for (int k = 0; k < 3; ++k) {
      s.gyro_rps[k] += bg[k] + imu.gyro_noise_density / std::sqrt(dt) * n01(rng);
      s.accel_mps2[k] += ba[k] + imu.accel_noise_density / std::sqrt(dt) * n01(rng);
    }
    out.samples.push_back(s);
    out.gyro_bias.push_back(bg);
    for (int k = 0; k < 3; ++k) {
      bg[k] += imu.gyro_random_walk * std::sqrt(dt) * n01(rng);
      ba[k] += imu.accel_random_walk * std::sqrt(dt) * n01(rng);
    }
  }
  return out;
}

Pose truth_camera(const SyntheticMotion& m, const Pose& T_b_c, std::int64_t t_ns) {
  const MotionPoint p = m.at(1e-9 * static_cast<double>(t_ns));
  Pose T = Pose::Identity();
  T.linear() = p.R_w_b;
  T.translation() = p.p_w_b_m;
  return T * T_b_c;
}

// range(0): gyro-bias estimate off/on; range(1): GICP rotation noise, millidegrees;
// range(2): GICP translation noise, mm; range(3): gain in percent per frame;
// range(4): velocity reset 0 = difference (the paper), 1 = imu-corrected.
void BM_GyroBiasDrift(benchmark::State& state) {
  const bool estimate = state.range(0) != 0;
  const double rot_noise_rad = 1e-3 * static_cast<double>(state.range(1)) * M_PI / 180.0;
  const double pos_noise_m = 1e-3 * static_cast<double>(state.range(2));
  const vigs::config::ImuSettings imu;  // built-in densities
  vigs::config::InertialSettings inertial;
  inertial.estimate_gyro_bias = estimate;
  inertial.gyro_bias_gain = 0.01 * static_cast<double>(state.range(3));
  inertial.velocity_reset = state.range(4) != 0 ? "imu" : "difference";
  const auto opts =
      InertialFrontendOptions::from(imu, vigs::config::ExtrinsicsSettings{}, inertial);
  const SyntheticMotion motion;
  const double duration_s = 60.0, warmup_s = 5.0;
  const SimImu sim = simulate_imu(motion, imu, duration_s + 2.0, 42);

  vigs::bench::DriftStats stats;
  for (auto _ : state) {
    std::mt19937 rng(7);
    std::normal_distribution<double> n01(0.0, 1.0);
    InertialFrontend f(opts);
    std::size_t next = 0;
    auto feed = [&](InertialFrontend& fe, std::size_t& idx, std::int64_t t_ns) {
      while (idx < sim.samples.size() && sim.samples[idx].t_ns <= t_ns + 10'000'000) {
        fe.add_sample(sim.samples[idx++]);
      }
    };
    const std::int64_t frame_ns = 50'000'000;
    for (std::int64_t t = 1'000'000; t < static_cast<std::int64_t>(duration_s * 1e9);
         t += frame_ns) {
      feed(f, next, t);
      const auto guess = f.predict_camera_pose(t);
      const Pose truth = truth_camera(motion, opts.T_b_c, t);
      const bool scored = t > static_cast<std::int64_t>(warmup_s * 1e9);
      if (guess && scored) {
        const auto e = vigs::geometry::pose_error(*guess, truth);
        stats.add_guess(e);
        const auto k = static_cast<std::size_t>(t / 5'000'000);
        stats.add_bias_error_sq((f.bias_gyro_rps() - sim.gyro_bias[k]).squaredNorm());
      }
      Pose tracked = truth;
      tracked.linear() = truth.linear() * vigs::geometry::so3_exp<double>(Vector3d(
                                              rot_noise_rad * n01(rng), rot_noise_rad * n01(rng),
                                              rot_noise_rad * n01(rng)));
      tracked.translation() += pos_noise_m * Vector3d(n01(rng), n01(rng), n01(rng));
      f.reset_from_tracked(t, tracked);
      // A 1 s tracking outage starting here, every 2 s: IMU-only dead reckoning.
      if (scored && (t / frame_ns) % 40 == 0) {
        InertialFrontend outage = f;
        std::size_t idx = next;
        const std::int64_t t_end = t + 1'000'000'000;
        feed(outage, idx, t_end);
        if (const auto p = outage.predict_camera_pose(t_end)) {
          const auto e = vigs::geometry::pose_error(*p, truth_camera(motion, opts.T_b_c, t_end));
          stats.add_drift(e);
        }
      }
    }
  }
  stats.report(state, /*guess_position=*/true, /*bias=*/true);
  state.SetLabel(estimate ? "gyro-bias estimate on" : "off (baseline)");
}
BENCHMARK(BM_GyroBiasDrift)
    ->ArgNames({"estimate", "rot_mdeg", "pos_mm", "gain_pct", "vel_imu"})
    ->Args({0, 20, 2, 10, 0})
    ->Args({1, 20, 2, 10, 0})
    ->Args({0, 50, 5, 10, 0})
    ->Args({1, 50, 5, 10, 0})
    ->Args({1, 50, 5, 3, 0})
    ->Args({1, 20, 2, 10, 1})
    ->Args({1, 0, 0, 10, 0})
    ->Args({1, 0, 0, 10, 1})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

namespace {

// The same measurement on real data: EuRoC V1_02's IMU, with its ground-truth body poses at
// 20 Hz standing in for GICP results (no added noise; the Vicon-based ground truth has its own
// ~mm / ~0.1 deg errors). Biases start at zero; the accelerometer bias is not estimated.
// bias_err_final_rps compares the estimate with the ground-truth gyro bias at the end.
void BM_GyroBiasDriftEurocV102(benchmark::State& state) {
  const bool estimate = state.range(0) != 0;
  const std::string dir = std::string(VIGS_SHARED_DATA_DIR) + "/euroc_v102/";
  std::vector<ImuSample> imu;
  std::vector<GroundTruthState> gt;
  try {
    imu = read_euroc_imu_csv(dir + "imu0.csv");
    gt = read_euroc_groundtruth_csv(dir + "groundtruth.csv");
  } catch (const EurocCsvError& e) {
    state.SkipWithError(e.what());
    return;
  }
  vigs::config::InertialSettings inertial;
  inertial.estimate_gyro_bias = estimate;
  const vigs::config::ImuSettings imu_settings;
  const auto opts =
      InertialFrontendOptions::from(imu_settings, vigs::config::ExtrinsicsSettings{}, inertial);
  auto T_w_c = [&](const GroundTruthState& g) {
    Pose T = Pose::Identity();
    T.linear() = g.q_w_b.toRotationMatrix();
    T.translation() = g.p_w_b_m;
    return T * opts.T_b_c;
  };
  vigs::bench::DriftStats stats;
  Vector3d final_err = Vector3d::Zero();
  for (auto _ : state) {
    InertialFrontend f(opts);
    std::size_t next = 0;
    auto feed = [&](InertialFrontend& fe, std::size_t& idx, std::int64_t t_ns) {
      while (idx < imu.size() && imu[idx].t_ns <= t_ns + 10'000'000) fe.add_sample(imu[idx++]);
    };
    const std::int64_t t_first = gt.front().t_ns;
    for (std::size_t k = 0; k < gt.size(); k += 10) {  // 200 Hz ground truth -> 20 Hz frames
      const std::int64_t t = gt[k].t_ns;
      if (t + 1'000'000'000 > imu.back().t_ns) break;
      feed(f, next, t);
      const auto guess = f.predict_camera_pose(t);
      const bool scored = t - t_first > 5'000'000'000;
      if (guess && scored) {
        const auto e = vigs::geometry::pose_error(*guess, T_w_c(gt[k]));
        stats.add_guess(e);
      }
      f.reset_from_tracked(t, T_w_c(gt[k]));
      final_err = f.bias_gyro_rps() - gt[k].bias_gyro_rps;
      if (scored && (k / 10) % 40 == 0 && k + 200 < gt.size()) {
        InertialFrontend outage = f;
        std::size_t idx = next;
        const GroundTruthState& end = gt[k + 200];  // 1 s later
        feed(outage, idx, end.t_ns);
        if (const auto p = outage.predict_camera_pose(end.t_ns)) {
          const auto e = vigs::geometry::pose_error(*p, T_w_c(end));
          stats.add_drift(e);
        }
      }
    }
  }
  stats.report(state, /*guess_position=*/false, /*bias=*/false);
  state.counters["bias_err_final_rps"] = final_err.norm();
  state.SetLabel(estimate ? "gyro-bias estimate on" : "off (baseline)");
}
BENCHMARK(BM_GyroBiasDriftEurocV102)
    ->ArgName("estimate")
    ->Arg(0)
    ->Arg(1)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace
