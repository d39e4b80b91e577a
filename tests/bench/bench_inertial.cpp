// bench_inertial: speed of preintegration and of the IMU-seeded initial guess, each beside a
// naive re-integration baseline in the same run. The drift benefit of the gyro-bias estimate
// is in bench_inertial_sim.cpp (project simulator), bench_inertial_drift.cpp (analytic
// trajectory, EuRoC V1_02): counters, iterations fixed at 1, so the time column means
// nothing there. Other sources in this target must not define main (BENCHMARK_MAIN is here).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/config/extrinsics_settings.hpp"
#include "core/config/imu_settings.hpp"
#include "core/config/inertial_settings.hpp"
#include "core/geometry/se3.hpp"
#include "inertial/inertial_frontend.hpp"
#include "inertial/nav_state.hpp"
#include "inertial/preintegrate_window.hpp"
#include "inertial/synthetic_motion.hpp"

namespace {

using Eigen::Vector3d;
using vigs::ImuSample;
using vigs::geometry::Pose;
using namespace vigs::inertial;

constexpr std::int64_t kImuPeriodNs = 5'000'000;     // 200 Hz
constexpr std::int64_t kFramePeriodNs = 50'000'000;  // 20 Hz
const Vector3d kGravity(0, 0, -9.81);

std::vector<ImuSample> clean_samples(int n) {
  SyntheticMotion m;
  std::vector<ImuSample> out;
  out.reserve(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) out.push_back(m.sample(k * kImuPeriodNs, kGravity));
  return out;
}

InertialFrontendOptions default_options() {
  return InertialFrontendOptions::from(vigs::config::ImuSettings{},
                                       vigs::config::ExtrinsicsSettings{},
                                       vigs::config::InertialSettings{});
}

Pose camera_pose(const SyntheticMotion& m, const Pose& T_b_c, std::int64_t t_ns) {
  const MotionPoint p = m.at(1e-9 * static_cast<double>(t_ns));
  Pose T = Pose::Identity();
  T.linear() = p.R_w_b;
  T.translation() = p.p_w_b_m;
  return T * T_b_c;
}

// ---- speed -------------------------------------------------------------------------------

// One 200 Hz sample into a running preintegration (restarted every 1 s of samples).
void BM_IntegrateOneSample(benchmark::State& state) {
  const auto scheme = static_cast<IntegrationScheme>(state.range(0));
  const auto samples = clean_samples(201);
  Preintegrator pi(scheme, ImuNoise{1.7e-4, 2e-3});
  pi.reset(samples[0], Vector3d::Zero(), Vector3d::Zero());
  std::size_t k = 1;
  for (auto _ : state) {
    pi.integrate(samples[k]);
    if (++k == samples.size()) {
      k = 1;
      pi.reset(samples[0], Vector3d::Zero(), Vector3d::Zero());
    }
  }
  benchmark::DoNotOptimize(pi.delta().p_m);
  state.SetLabel(integration_scheme_name(scheme));
}
BENCHMARK(BM_IntegrateOneSample)->Arg(0)->Arg(1);

// A bias change applied to an integrated window: first-order correction through the bias
// Jacobians (range(0) = window samples) ...
void BM_BiasUpdate_Jacobian(benchmark::State& state) {
  const auto samples = clean_samples(static_cast<int>(state.range(0)) + 1);
  Preintegrator pi(IntegrationScheme::kMidpoint, ImuNoise{1.7e-4, 2e-3});
  preintegrate_window(samples, 0, samples.back().t_ns, Vector3d::Zero(), Vector3d::Zero(), pi);
  Vector3d bg(1e-3, -2e-3, 3e-3);
  for (auto _ : state) {
    bg.x() += 1e-9;
    benchmark::DoNotOptimize(pi.predict_with_bias(bg, Vector3d::Zero()));
  }
}
BENCHMARK(BM_BiasUpdate_Jacobian)->Arg(10)->Arg(200);

// ... beside the naive baseline: re-integrating the whole window with the new bias.
void BM_BiasUpdate_NaiveReintegration(benchmark::State& state) {
  const auto samples = clean_samples(static_cast<int>(state.range(0)) + 1);
  Preintegrator pi(IntegrationScheme::kMidpoint, ImuNoise{1.7e-4, 2e-3});
  Vector3d bg(1e-3, -2e-3, 3e-3);
  for (auto _ : state) {
    bg.x() += 1e-9;
    preintegrate_window(samples, 0, samples.back().t_ns, bg, Vector3d::Zero(), pi);
    benchmark::DoNotOptimize(pi.delta());
  }
}
BENCHMARK(BM_BiasUpdate_NaiveReintegration)->Arg(10)->Arg(200);

// One frame's guess with the frontend: 10 new samples queued, the camera pose predicted
// (each sample integrated once, plus one interpolated partial step and the composition), and
// the tracked pose fed back (reset + gyro-bias update).
void BM_FrameGuess_Frontend(benchmark::State& state) {
  const SyntheticMotion motion;
  const auto opts = default_options();
  const auto samples = clean_samples(20 * 200 + 20);
  std::vector<Pose> truth;
  for (int k = 0; k < 200; ++k)
    truth.push_back(camera_pose(motion, opts.T_b_c, k * kFramePeriodNs + 1'000'000));
  InertialFrontend f(opts);
  std::size_t s = 0;
  int frame = 0;
  for (auto _ : state) {
    if (frame == 200) {
      state.PauseTiming();
      f = InertialFrontend(opts);
      s = 0;
      frame = 0;
      state.ResumeTiming();
    }
    const std::int64_t t = frame * kFramePeriodNs + 1'000'000;
    while (samples[s].t_ns <= t + kImuPeriodNs) f.add_sample(samples[s++]);
    benchmark::DoNotOptimize(f.predict_camera_pose(t));
    f.reset_from_tracked(t, truth[static_cast<std::size_t>(frame)]);
    ++frame;
  }
}
BENCHMARK(BM_FrameGuess_Frontend);

// Composing the guess alone, once the frame's samples are integrated: copy of the
// integrator, one partial step, prediction and the four-pose composition.
void BM_FrameGuess_ComposeOnly(benchmark::State& state) {
  const SyntheticMotion motion;
  const auto opts = default_options();
  const auto samples = clean_samples(40);
  InertialFrontend f(opts);
  for (const auto& s : samples) f.add_sample(s);
  f.reset_from_tracked(1'000'000, camera_pose(motion, opts.T_b_c, 1'000'000));
  const std::int64_t t = 51'000'000;
  benchmark::DoNotOptimize(f.predict_camera_pose(t));  // integrates the frame's samples
  for (auto _ : state) benchmark::DoNotOptimize(f.predict_camera_pose(t));
}
BENCHMARK(BM_FrameGuess_ComposeOnly);

// Naive baseline: keep every sample since the last tracked frame and re-integrate that whole
// window from scratch for the guess (range(0) = frames since the reference, at 20 Hz).
void BM_FrameGuess_NaiveReintegration(benchmark::State& state) {
  const SyntheticMotion motion;
  const auto opts = default_options();
  const int frames = static_cast<int>(state.range(0));
  const auto samples = clean_samples(10 * frames + 4);
  const std::int64_t t_i = 1'000'000, t_j = t_i + frames * kFramePeriodNs;
  const Pose T_w_c_i = camera_pose(motion, opts.T_b_c, t_i);
  const MotionPoint m = motion.at(1e-9 * static_cast<double>(t_i));
  const NavState s_i{m.R_w_b, m.p_w_b_m, m.v_w_b_mps};
  Preintegrator pi(opts.scheme, opts.noise);
  for (auto _ : state) {
    preintegrate_window(samples, t_i, t_j, Vector3d::Zero(), Vector3d::Zero(), pi);
    const NavState s_j = predict_nav_state(s_i, pi.delta(), opts.g_w_mps2);
    const Pose guess = T_w_c_i * opts.T_b_c.inverse() * relative_body_motion(s_i, s_j) * opts.T_b_c;
    benchmark::DoNotOptimize(guess);
  }
}
BENCHMARK(BM_FrameGuess_NaiveReintegration)->Arg(1)->Arg(20);

}  // namespace

BENCHMARK_MAIN();
