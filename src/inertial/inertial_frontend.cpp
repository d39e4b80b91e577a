#include "inertial/inertial_frontend.hpp"

#include <algorithm>
#include <cmath>

#include "core/geometry/body_from_camera.hpp"
#include "inertial/imu_interpolation.hpp"

namespace vigs::inertial {
namespace {

StillnessOptions stillness_options(const InertialFrontendOptions& o) {
  StillnessOptions s;
  s.window_s = o.zupt_window_s;
  const double sqrt_rate = std::sqrt(std::max(o.rate_hz, 1.0));
  s.accel_sigma_mps2 = o.noise.accel_noise_density * sqrt_rate;
  // Room for a stretch of lost frames the fused update bridges (longer ones are never still).
  s.capacity = std::max(2, o.buffer_capacity);
  return s;
}

}  // namespace

InertialFrontendOptions InertialFrontendOptions::from(const config::ImuSettings& imu,
                                                      const config::ExtrinsicsSettings& extrinsics,
                                                      const config::InertialSettings& inertial) {
  InertialFrontendOptions o;
  if (!parse_integration_scheme(inertial.scheme, o.scheme)) {
    o.scheme = IntegrationScheme::kMidpoint;  // the config schema admits only the two names
  }
  o.noise = ImuNoise::from(imu);
  o.g_w_mps2 = gravity_w(imu.gravity_mps2);
  o.T_b_c = geometry::body_from_camera(extrinsics);
  o.time_offset_ns = static_cast<std::int64_t>(std::llround(imu.time_offset_s * 1e9));
  o.buffer_capacity = inertial.buffer_capacity;
  o.velocity_reset =
      inertial.velocity_reset == "imu" ? VelocityReset::kImu : VelocityReset::kDifference;
  o.estimate_gyro_bias = inertial.estimate_gyro_bias;
  o.bias = GyroBiasEstimatorOptions::from(inertial);
  o.gyro_random_walk = imu.gyro_random_walk;
  o.accel_random_walk = imu.accel_random_walk;
  o.initial_velocity_sigma_mps = inertial.fused_initial_velocity_sigma_mps;
  o.initial_gyro_bias_sigma_rps = inertial.fused_initial_gyro_bias_sigma_rps;
  o.initial_accel_bias_sigma_mps2 = inertial.fused_initial_accel_bias_sigma_mps2;
  o.estimate_accel_bias = inertial.estimate_accel_bias;
  o.extra_accel_noise_density = inertial.fused_extra_accel_noise_density;
  o.extra_accel_random_walk = inertial.fused_extra_accel_random_walk;
  o.initial_gravity_tilt_sigma_rad = inertial.fused_gravity_tilt_sigma_rad;
  o.gravity_tilt_random_walk = inertial.fused_gravity_tilt_random_walk;
  o.zupt = inertial.fused_zupt;
  o.zupt_window_s = inertial.fused_zupt_window_s;
  o.zupt_threshold = inertial.fused_zupt_threshold;
  o.zupt_sigma_mps = inertial.fused_zupt_sigma_mps;
  o.zupt_max_tracked_speed_mps = inertial.fused_zupt_max_tracked_speed_mps;
  o.rate_hz = imu.rate_hz;
  return o;
}

InertialFrontend::InertialFrontend(const InertialFrontendOptions& options)
    : options_(options),
      queue_(static_cast<std::size_t>(std::max(2, options.buffer_capacity))),
      pi_(options.scheme, options.noise),
      bias_(options.bias),
      still_(stillness_options(options)),
      g_w_mps2_(options.g_w_mps2) {}

void InertialFrontend::set_biases(const Eigen::Vector3d& gyro_rps,
                                  const Eigen::Vector3d& accel_mps2) {
  bias_.set_bias_rps(gyro_rps);
  bias_accel_mps2_ = accel_mps2;
}

bool InertialFrontend::add_sample(const ImuSample& s) {
  if (s.t_ns < last_queued_t_ns_) {
    ++counters_.samples_out_of_order;
    return false;
  }
  if (queue_.push_back(s)) ++counters_.samples_dropped;
  last_queued_t_ns_ = s.t_ns;
  ++counters_.samples_added;
  return true;
}

void InertialFrontend::advance_to(std::int64_t t_ns) {
  while (!queue_.empty() && queue_.front().t_ns <= t_ns) {
    const ImuSample s = queue_.front();
    queue_.pop_front();
    if (started_ && s.t_ns > pi_.t_end_ns()) pi_.integrate(s);
    still_.add(s);
    last_consumed_ = s;
    has_consumed_ = true;
  }
}

ImuSample InertialFrontend::reading_at(std::int64_t t_ns) {
  if (has_consumed_ && last_consumed_.t_ns == t_ns) return last_consumed_;
  if (!queue_.empty()) {
    if (has_consumed_) return interpolate_sample(last_consumed_, queue_.front(), t_ns);
    ++counters_.extrapolated;
    return interpolate_sample(queue_.front(), queue_.front(), t_ns);
  }
  ++counters_.extrapolated;
  return interpolate_sample(last_consumed_, last_consumed_, t_ns);
}

std::optional<NavState> InertialFrontend::predict_state(std::int64_t t_cam_ns) {
  const std::int64_t t_ns = t_cam_ns + options_.time_offset_ns;
  if (!started_ || t_ns < pi_.t_end_ns()) return std::nullopt;
  advance_to(t_ns);
  Preintegrator p = pi_;
  if (t_ns > p.t_end_ns()) p.integrate(reading_at(t_ns));
  const DeltaState d = p.predict_with_bias(bias_.bias_rps(), bias_accel_mps2_);
  return predict_nav_state(state_, d, g_w_mps2_);
}

std::optional<geometry::Pose> InertialFrontend::predict_camera_pose(std::int64_t t_ns) {
  const std::optional<NavState> s = predict_state(t_ns);
  if (!s) return std::nullopt;
  // T_w_c(k) = T_w_c(k-1) * T_c_b * T_b(k-1 -> k) * T_b_c
  return T_w_c_last_ * options_.T_b_c.inverse() * relative_body_motion(state_, *s) * options_.T_b_c;
}

bool InertialFrontend::reset_from_tracked(std::int64_t t_cam_ns, const geometry::Pose& T_w_c) {
  const std::int64_t t_ns = t_cam_ns + options_.time_offset_ns;
  if (started_ && t_ns < pi_.t_end_ns()) return false;
  advance_to(t_ns);
  const ImuSample r = reading_at(t_ns);
  const geometry::Pose T_w_b = T_w_c * options_.T_b_c.inverse();
  NavState s;
  s.R_w_b = T_w_b.linear();
  s.p_w_b_m = T_w_b.translation();
  if (started_) {
    if (t_ns > pi_.t_end_ns()) pi_.integrate(r);
    if (options_.estimate_gyro_bias) {
      bias_.update(pi_, Eigen::Matrix3d(state_.R_w_b.transpose() * s.R_w_b));
    }
    const double dt_s = 1e-9 * static_cast<double>(t_ns - t_last_ns_);
    if (dt_s > 0.0) {
      const Eigen::Vector3d dp_w = s.p_w_b_m - state_.p_w_b_m;
      if (options_.velocity_reset == VelocityReset::kImu) {
        // p_k = p_{k-1} + v_{k-1} dt + g dt^2/2 + R_{k-1} dp gives v_{k-1}; then
        // v_k = v_{k-1} + g dt + R_{k-1} dv.
        const DeltaState d = pi_.predict_with_bias(bias_.bias_rps(), bias_accel_mps2_);
        const Eigen::Vector3d g = g_w_mps2_;
        const Eigen::Vector3d v_prev = (dp_w - 0.5 * g * dt_s * dt_s - state_.R_w_b * d.p_m) / dt_s;
        s.v_w_b_mps = v_prev + g * dt_s + state_.R_w_b * d.v_mps;
      } else {
        s.v_w_b_mps = dp_w / dt_s;
      }
    } else {
      s.v_w_b_mps = state_.v_w_b_mps;
    }
  }
  state_ = s;
  T_w_c_last_ = T_w_c;
  t_last_ns_ = t_ns;
  started_ = true;
  pi_.reset(r, bias_.bias_rps(), bias_accel_mps2_);
  ++counters_.resets;
  return true;
}

bool InertialFrontend::propagate_fused(std::int64_t t_ns, bool commit, NavState& s_pred,
                                       MatS& P_pred) {
  if (!started_ || t_ns < pi_.t_end_ns()) return false;
  advance_to(t_ns);
  Preintegrator scratch;
  const Preintegrator* p = &pi_;
  if (t_ns > pi_.t_end_ns()) {
    if (commit) {
      pi_.integrate(reading_at(t_ns));
    } else {
      scratch = pi_;
      scratch.integrate(reading_at(t_ns));
      p = &scratch;
    }
  }
  s_pred = predict_nav_state(state_, p->delta(), g_w_mps2_);
  MatS Phi;
  MatSx9 G;
  prediction_jacobians(state_, *p, g_w_mps2_, Phi, G);
  P_pred = Phi * P_ * Phi.transpose() + G * p->covariance() * G.transpose();
  const double dt = p->dt_s();
  const double qg = options_.gyro_random_walk * options_.gyro_random_walk * dt;
  const double ra = options_.accel_random_walk, xa = options_.extra_accel_random_walk;
  const double qa = options_.estimate_accel_bias ? (ra * ra + xa * xa) * dt : 0.0;
  P_pred.block<3, 3>(9, 9).diagonal().array() += qg;
  P_pred.block<3, 3>(12, 12).diagonal().array() += qa;
  const double rt = options_.gravity_tilt_random_walk;
  P_pred.block<2, 2>(kGravityRow, kGravityRow).diagonal().array() += rt * rt * dt;

  // At rest over the interval: no unmodelled acceleration, and the velocity measured as 0.
  if (options_.zupt) {
    const std::optional<double> T = still_.statistic(t_last_ns_, t_ns);
    if (T && *T <= options_.zupt_threshold) {
      VecS dx;
      double mahalanobis = 0.0;
      if (tracked_speed_mps_ <= options_.zupt_max_tracked_speed_mps &&
          zero_velocity_update(s_pred.v_w_b_mps, options_.zupt_sigma_mps, kZuptGate, P_pred, dx,
                               mahalanobis)) {
        s_pred.R_w_b = geometry::so3_exp<double>(Eigen::Vector3d(dx.head<3>())) * s_pred.R_w_b;
        s_pred.p_w_b_m += dx.segment<3>(3);
        s_pred.v_w_b_mps += dx.segment<3>(6);
        if (commit) {
          correct_biases(dx);
          ++counters_.zero_velocity_updates;
        }
        return true;
      }
      if (commit) ++counters_.zupt_gated;
    }
  }
  // Unmodelled white acceleration q over dt (isotropic, so the frame does not matter):
  // Q_pp = q dt^3/3, Q_pv = q dt^2/2, Q_vv = q dt.
  const double q = options_.extra_accel_noise_density * options_.extra_accel_noise_density;
  if (q > 0.0) {
    P_pred.block<3, 3>(3, 3).diagonal().array() += q * dt * dt * dt / 3.0;
    P_pred.block<3, 3>(3, 6).diagonal().array() += q * dt * dt / 2.0;
    P_pred.block<3, 3>(6, 3).diagonal().array() += q * dt * dt / 2.0;
    P_pred.block<3, 3>(6, 6).diagonal().array() += q * dt;
  }
  return true;
}

void InertialFrontend::correct_biases(const VecS& dx) {
  bias_.set_bias_rps(bias_.bias_rps() + dx.segment<3>(9));
  if (options_.estimate_accel_bias) bias_accel_mps2_ += dx.segment<3>(12);
  // Zero while the tilt is pinned (prior sigma and random walk 0: its rows of P stay 0).
  const Eigen::Vector3d tilt(dx(kGravityRow), dx(kGravityRow + 1), 0.0);
  g_w_mps2_ = geometry::so3_exp<double>(tilt) * g_w_mps2_;
}

std::optional<InertialFrontend::PosePrediction> InertialFrontend::predict_camera_pose_fused(
    std::int64_t t_cam_ns) {
  const std::int64_t t_ns = t_cam_ns + options_.time_offset_ns;
  NavState s;
  MatS P;
  if (!propagate_fused(t_ns, false, s, P)) return std::nullopt;
  PosePrediction out;
  out.T_w_c = s.T_w_b() * options_.T_b_c;
  const Mat6xS J = camera_pose_jacobian(s.p_w_b_m);
  out.covariance = J * P * J.transpose();
  return out;
}

bool InertialFrontend::update_fused(std::int64_t t_cam_ns, const geometry::Pose& T_w_c,
                                    const Mat6& information) {
  const std::int64_t t_ns = t_cam_ns + options_.time_offset_ns;
  const geometry::Pose T_w_b = T_w_c * options_.T_b_c.inverse();
  NavState s;
  if (!started_) {
    advance_to(t_ns);
    tracked_speed_mps_ = 0.0;  // the first frame starts at rest
    s.R_w_b = T_w_b.linear();
    s.p_w_b_m = T_w_b.translation();
    // The first frame defines the world: its pose is exact; the body starts at rest.
    P_.setZero();
    P_.block<3, 3>(0, 0).diagonal().setConstant(1e-12);
    P_.block<3, 3>(3, 3).diagonal().setConstant(1e-12);
    const double sv = options_.initial_velocity_sigma_mps;
    const double sg = options_.initial_gyro_bias_sigma_rps;
    const double sa = options_.estimate_accel_bias ? options_.initial_accel_bias_sigma_mps2 : 0.0;
    P_.block<3, 3>(6, 6).diagonal().setConstant(sv * sv);
    P_.block<3, 3>(9, 9).diagonal().setConstant(sg * sg);
    P_.block<3, 3>(12, 12).diagonal().setConstant(sa * sa);
    const double st = options_.initial_gravity_tilt_sigma_rad;
    P_.block<2, 2>(kGravityRow, kGravityRow).diagonal().setConstant(st * st);
  } else {
    MatS P;
    if (!propagate_fused(t_ns, true, s, P)) return false;
    P_ = P;
    const Mat6xS J = camera_pose_jacobian(s.p_w_b_m);
    const geometry::Pose T_w_c_pred = s.T_w_b() * options_.T_b_c;
    // e* of the fused pose relative to the prediction (tracking/pose_prior.hpp convention).
    const Eigen::Matrix3d dR = T_w_c.linear() * T_w_c_pred.linear().transpose();
    Vec6 e;
    e.head<3>() = geometry::so3_log<double>(dR);
    e.tail<3>() = T_w_c.translation() - dR * T_w_c_pred.translation();
    VecS dx;
    if (fused_pose_update(J, e, information, P_, dx)) {
      s.v_w_b_mps += dx.segment<3>(6);
      correct_biases(dx);
    }
    // R and p exactly the fused pose's (dx's pose part is e* to first order).
    s.R_w_b = T_w_b.linear();
    s.p_w_b_m = T_w_b.translation();
    const double dt_s = 1e-9 * static_cast<double>(t_ns - t_last_ns_);
    tracked_speed_mps_ = dt_s > 0.0 ? (s.p_w_b_m - state_.p_w_b_m).norm() / dt_s : 0.0;
  }
  state_ = s;
  T_w_c_last_ = T_w_c;
  t_last_ns_ = t_ns;
  started_ = true;
  pi_.reset(reading_at(t_ns), bias_.bias_rps(), bias_accel_mps2_);
  ++counters_.resets;
  return true;
}

}  // namespace vigs::inertial
