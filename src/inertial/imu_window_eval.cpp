#include "inertial/imu_window_eval.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/geometry/se3.hpp"
#include "inertial/nav_state.hpp"
#include "inertial/preintegrate_window.hpp"

namespace vigs::inertial {

namespace {
struct Accumulator {
  double sum_sq = 0.0;
  double max = 0.0;
  void add(double e) {
    sum_sq += e * e;
    max = std::max(max, e);
  }
  [[nodiscard]] ErrorStats stats(int n) const { return {n > 0 ? std::sqrt(sum_sq / n) : 0.0, max}; }
};
constexpr double kRadToDeg = 180.0 / M_PI;
}  // namespace

WindowEvalResult evaluate_imu_windows(std::span<const ImuSample> imu,
                                      std::span<const GroundTruthState> gt,
                                      const WindowEvalOptions& options) {
  if (!(options.window_s > 0.0)) throw std::invalid_argument("window must be positive");
  if (imu.empty() || gt.empty()) throw std::invalid_argument("empty IMU or ground truth");
  const auto window_ns = static_cast<std::int64_t>(std::llround(options.window_s * 1e9));
  const auto max_gap_ns = static_cast<std::int64_t>(std::llround(options.max_gap_s * 1e9));
  const Eigen::Vector3d g_w = gravity_w(options.gravity_mps2);

  Accumulator rot, vel, pos, s_rot, s_vel, s_pos;
  WindowEvalResult res;
  double total_s = 0.0;
  Preintegrator pi(options.scheme, options.noise);
  std::size_t i = 0;
  while (i < gt.size() && gt[i].t_ns < imu.front().t_ns) ++i;
  while (i < gt.size()) {
    // End of the window: the first ground-truth stamp at least window_s later.
    const std::int64_t target = gt[i].t_ns + window_ns;
    const auto it =
        std::lower_bound(gt.begin() + static_cast<std::ptrdiff_t>(i), gt.end(), target,
                         [](const GroundTruthState& g, std::int64_t t) { return g.t_ns < t; });
    if (it == gt.end()) break;
    const std::size_t j = static_cast<std::size_t>(it - gt.begin());
    const GroundTruthState& a = gt[i];
    const GroundTruthState& b = gt[j];
    if (b.t_ns > imu.back().t_ns) break;
    i = j;
    if (largest_gap_ns(imu, a.t_ns, b.t_ns) > max_gap_ns) {
      ++res.skipped_gap;
      continue;
    }
    const bool gt_bias = options.bias == BiasSource::kGroundTruth;
    const Eigen::Vector3d bg = gt_bias ? a.bias_gyro_rps : Eigen::Vector3d::Zero();
    const Eigen::Vector3d ba = gt_bias ? a.bias_accel_mps2 : Eigen::Vector3d::Zero();
    if (!preintegrate_window(imu, a.t_ns, b.t_ns, bg, ba, pi)) continue;

    NavState s0;
    s0.R_w_b = a.q_w_b.toRotationMatrix();
    s0.p_w_b_m = a.p_w_b_m;
    s0.v_w_b_mps = a.v_w_b_mps;
    const NavState s1 = predict_nav_state(s0, pi.delta(), g_w);

    rot.add(kRadToDeg *
            geometry::rotation_angle(s1.R_w_b.transpose() * b.q_w_b.toRotationMatrix()));
    vel.add((s1.v_w_b_mps - b.v_w_b_mps).norm());
    pos.add((s1.p_w_b_m - b.p_w_b_m).norm());
    const auto& C = pi.covariance();
    s_rot.add(kRadToDeg * std::sqrt(C.block<3, 3>(0, 0).trace()));
    s_vel.add(std::sqrt(C.block<3, 3>(3, 3).trace()));
    s_pos.add(std::sqrt(C.block<3, 3>(6, 6).trace()));
    total_s += pi.dt_s();
    ++res.windows;
  }
  if (res.windows == 0) {
    throw std::invalid_argument("IMU and ground truth do not overlap by one whole window");
  }
  res.mean_window_s = total_s / res.windows;
  res.rotation_deg = rot.stats(res.windows);
  res.velocity_mps = vel.stats(res.windows);
  res.position_m = pos.stats(res.windows);
  res.sigma_rotation_deg = s_rot.stats(res.windows).rms;
  res.sigma_velocity_mps = s_vel.stats(res.windows).rms;
  res.sigma_position_m = s_pos.stats(res.windows).rms;
  return res;
}

}  // namespace vigs::inertial
