#include "sim/simulator.hpp"

#include <chrono>
#include <cmath>
#include <future>
#include <utility>

#include "core/geometry/body_from_camera.hpp"
#include "sim/floor_plan.hpp"
#include "sim/realistic_motion.hpp"
#include "sim/spline_trajectory.hpp"

namespace vigs::sim {
namespace {

RenderSettings render_settings(const config::RobotConfig& c) {
  RenderSettings r;
  r.min_depth_m = static_cast<float>(c.camera.min_depth_m);
  r.max_depth_m = static_cast<float>(c.camera.max_depth_m);
  r.depth_noise_base_m = static_cast<float>(c.sim.depth_noise_base_m);
  r.depth_noise_quadratic_per_m = static_cast<float>(c.sim.depth_noise_quadratic_per_m);
  r.hole_cos = static_cast<float>(c.sim.hole_incidence_cos);
  r.dropout_cos = static_cast<float>(c.sim.dropout_incidence_cos);
  r.rgb_noise_sigma = static_cast<float>(c.sim.rgb_noise_sigma);
  r.gray = c.sim.gray;
  r.threads = c.sim.render_threads;
  return r;
}

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

Simulator::Simulator(const config::RobotConfig& cfg)
    : cfg_(cfg),
      scene_(make_preset(cfg.sim.preset, static_cast<std::uint64_t>(cfg.sim.seed))),
      camera_(PinholeCamera::from_settings(cfg.camera)),
      T_b_c_(geometry::body_from_camera(cfg.extrinsics)) {
  TrajectoryParams tp;
  tp.spacing_m = cfg.sim.speed_mps * tp.knot_interval_s;
  tp.height_m = cfg.sim.camera_height_m;
  SplineTrajectory route(scene_.route, tp);
  if (cfg.sim.motion == "realistic") {
    RealisticMotionParams rp;
    rp.cruise_mps = cfg.sim.speed_mps;
    trajectory_ = std::make_unique<RealisticMotion>(std::move(route),
                                                    static_cast<std::uint64_t>(cfg.sim.seed), rp);
  } else {
    trajectory_ = std::make_unique<SplineTrajectory>(std::move(route));
  }
  walkers_ = make_walkers(scene_, cfg.sim.humans, static_cast<std::uint64_t>(cfg.sim.seed));
  renderer_ = std::make_unique<Renderer>(scene_, camera_, render_settings(cfg));
  duration_s_ = cfg.sim.seconds > 0.0 ? std::min(cfg.sim.seconds, trajectory_->duration_s())
                                      : trajectory_->duration_s();
}

geometry::Pose Simulator::body_pose(double t_s) const {
  const BodyState st = trajectory_->state(t_s);
  geometry::Pose T = geometry::Pose::Identity();
  T.linear() = st.R_w_b;
  T.translation() = st.p_w_m;
  return T;
}

void Simulator::render_at(double t_s, std::uint64_t index, RgbdFrame& out) const {
  const PeopleSnapshot people(walkers_, t_s);
  renderer_->render(camera_pose(t_s), people,
                    hash3(static_cast<std::uint64_t>(cfg_.sim.seed), 0xF4A3E, index), out);
}

SimStats Simulator::run(SimSink& sink, const std::function<void(double, double)>& progress,
                        const std::atomic<bool>* stop) {
  const auto t_start = Clock::now();
  SimStats stats;
  stats.sequence_s = duration_s_;
  // Path lengths by integrating the spline's speed (10 ms steps, midpoint rule).
  for (double t = 0.005; t < trajectory_->duration_s(); t += 0.01) {
    const double ds = trajectory_->state(t).v_w_mps.norm() * 0.01;
    stats.route_length_m += ds;
    if (t < duration_s_) stats.sequence_length_m += ds;
  }

  ImuSynthesizer imu(cfg_.imu, static_cast<std::uint64_t>(cfg_.sim.seed));
  const auto imu_period_ns = static_cast<std::int64_t>(std::llround(1e9 / cfg_.imu.rate_hz));
  const auto frame_period_ns = static_cast<std::int64_t>(std::llround(1e9 / cfg_.camera.rate_hz));
  const auto end_ns = static_cast<std::int64_t>(std::llround(duration_s_ * 1e9));
  const std::int64_t n_frames = end_ns / frame_period_ns + 1;
  std::int64_t next_imu_ns = 0;
  // IMU and ground truth up to and including t_limit (at equal stamps they precede the frame).
  auto emit_imu_until = [&](std::int64_t t_limit) {
    for (; next_imu_ns <= t_limit && next_imu_ns <= end_ns; next_imu_ns += imu_period_ns) {
      const BodyState st = trajectory_->state(static_cast<double>(next_imu_ns) * 1e-9);
      sink.imu(imu.measure(st, next_imu_ns));
      geometry::Pose T_w_b = geometry::Pose::Identity();
      T_w_b.linear() = st.R_w_b;
      T_w_b.translation() = st.p_w_m;
      sink.ground_truth(next_imu_ns, T_w_b);
      ++stats.imu_samples;
    }
  };
  // Frame j+1 is rendered while frame j and the IMU samples after it are written: the sink
  // sees exactly the serial order, on this thread only. (Buffers outlive the future.)
  RgbdFrame buffers[2];
  std::future<double> rendering;
  auto launch = [&](std::int64_t j) {
    rendering = std::async(std::launch::async, [this, j, frame_period_ns, &buffers] {
      const auto t0 = Clock::now();
      render_at(static_cast<double>(j * frame_period_ns) * 1e-9, static_cast<std::uint64_t>(j),
                buffers[j % 2]);
      return seconds_since(t0);
    });
  };
  if (n_frames > 0) launch(0);
  for (std::int64_t j = 0; j < n_frames; ++j) {
    const std::int64_t t_ns = j * frame_period_ns;
    emit_imu_until(t_ns);
    stats.render_s += rendering.get();
    if (j + 1 < n_frames) launch(j + 1);
    sink.frame(t_ns, camera_, buffers[j % 2]);
    ++stats.frames;
    if (progress) progress(static_cast<double>(t_ns) * 1e-9, duration_s_);
    if (stop && stop->load(std::memory_order_relaxed)) {
      stats.stopped = true;
      if (j + 1 < n_frames) rendering.wait();  // frame j+1's buffers are in use until then
      stats.sequence_s = static_cast<double>(t_ns) * 1e-9;
      break;
    }
  }
  if (!stats.stopped) emit_imu_until(end_ns);
  stats.wall_s = seconds_since(t_start);
  return stats;
}

}  // namespace vigs::sim
