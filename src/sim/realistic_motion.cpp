#include "sim/realistic_motion.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace vigs::sim {
namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr double kTiny = 1e-9;

/// Cubic smoothstep and its derivative on tau in [0, 1] (clamped outside).
double smoothstep(double tau) {
  const double t = std::clamp(tau, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}
double smoothstep_slope(double tau) {
  return tau <= 0.0 || tau >= 1.0 ? 0.0 : 6.0 * tau * (1.0 - tau);
}

}  // namespace

RealisticMotion::RealisticMotion(SplineTrajectory path, std::uint64_t seed,
                                 const RealisticMotionParams& p)
    : path_(std::move(path)), p_(p), rng_(seed, 0x40710), profile_(path_.u_rest_end()) {
  // Control points are at most `spacing_m` apart, one per knot interval.
  spacing_m_ = path_.params().spacing_m;
  cruise_rate_ = p_.cruise_mps / spacing_m_;
  turn_rate_ = std::min(p_.turn_mps, p_.cruise_mps) / spacing_m_;
  plan_turns();
  const std::vector<Zone> zones = plan_zones();
  // At rest at the start (as the smooth route), then from zone to zone.
  profile_.hold(std::max(path_.params().standstill_s, 0.1));
  for (std::size_t i = 1; i < zones.size(); ++i) {
    const Zone& z = zones[i];
    fill_gap(z.a, z.rate);
    if (z.rate > 0.0 && z.b > profile_.u_end() + kTiny) {
      profile_.hold((z.b - profile_.u_end()) / z.rate);
    } else if (z.rate == 0.0 && z.dwell_s > 0.0) {
      profile_.hold(z.dwell_s);
    }
  }
  make_waves();
}

void RealisticMotion::plan_turns() {
  // A heading change between control points k and k+1 is centred at u = k - 0.5; a run of
  // consecutive changes is one corner, turned quickly around the run's centre.
  const std::vector<double>& yaw = path_.yaw_control_points();
  yaw0_rad_ = yaw.front();
  std::size_t k = 0;
  while (k + 1 < yaw.size()) {
    if (std::abs(yaw[k + 1] - yaw[k]) < kTiny) {
      ++k;
      continue;
    }
    double delta = 0.0, centre_sum = 0.0;
    int count = 0;
    for (; k + 1 < yaw.size() && std::abs(yaw[k + 1] - yaw[k]) >= kTiny; ++k, ++count) {
      delta += yaw[k + 1] - yaw[k];
      centre_sum += static_cast<double>(k) - 0.5;
    }
    const double peak_rps = rng_.uniform(p_.turn_rate_min_rps, p_.turn_rate_max_rps);
    // Smoothstep peak slope 1.5: peak yaw rate = 1.5 |delta| / (2 half) * turn rate.
    const double half = std::max(0.75 * std::abs(delta) * turn_rate_ / peak_rps, 0.05);
    turns_.push_back({centre_sum / count, half, delta});
  }
}

std::vector<RealisticMotion::Zone> RealisticMotion::plan_zones() {
  const double u_end = path_.u_end();
  std::vector<Zone> zones;
  zones.push_back({path_.u_rest_end(), path_.u_rest_end(), 0.0, 0.0});
  // Corners: slow zones, merged where there is no room to speed up in between.
  const double k_min = 1.5 * spacing_m_ / p_.accel_min_mps2;  // ramp seconds per unit rate
  const double between =
      2.0 * k_min * 0.5 * (cruise_rate_ * cruise_rate_ - turn_rate_ * turn_rate_);
  for (const Turn& t : turns_) {
    if (std::abs(t.delta_rad) < p_.min_turn_rad) continue;
    const double half = std::max(p_.corner_half_u, t.half_u + 0.2);
    const double a = std::max(t.center_u - half, path_.u_rest_end());
    const double b = std::min(t.center_u + half, u_end);
    if (zones.size() > 1 && a - zones.back().b < between) {
      zones.back().b = std::max(zones.back().b, b);
    } else {
      zones.push_back({a, b, turn_rate_, 0.0});
    }
  }
  zones.push_back({u_end, u_end, 0.0, 0.0});
  // Stops midway on the straights that have room to brake, stand and speed up again.
  std::vector<Zone> out;
  bool first = true;
  for (std::size_t i = 0; i + 1 < zones.size(); ++i) {
    out.push_back(zones[i]);
    const Zone &z0 = zones[i], &z1 = zones[i + 1];
    const double up = 0.5 * k_min * cruise_rate_ * cruise_rate_;  // from rest to cruise
    const double need = 0.5 * k_min * (cruise_rate_ * cruise_rate_ - z0.rate * z0.rate) + 2.0 * up +
                        0.5 * k_min * (cruise_rate_ * cruise_rate_ - z1.rate * z1.rate) + 1.0;
    if (i == 0 || z1.b >= u_end || z1.a - z0.b < need) continue;
    const double draw = rng_.uniform();
    if (!first && draw >= p_.stop_probability) continue;
    first = false;
    const double mid = 0.5 * (z0.b + z1.a);
    out.push_back({mid, mid, 0.0, rng_.uniform(p_.stop_min_s, p_.stop_max_s)});
  }
  out.push_back(zones.back());
  return out;
}

void RealisticMotion::fill_gap(double u_to, double rate_to) {
  const double r0 = profile_.rate();
  const double dist = u_to - profile_.u_end();
  const double k1 = 1.5 * spacing_m_ / rng_.uniform(p_.accel_min_mps2, p_.accel_max_mps2);
  const double k2 = 1.5 * spacing_m_ / rng_.uniform(p_.accel_min_mps2, p_.accel_max_mps2);
  // Peak rate reachable in `dist` with ramps of k seconds per unit rate: the ramps cover
  // k/2 |r_peak^2 - r^2| each.
  const double peak2 = (2.0 * dist + k1 * r0 * r0 + k2 * rate_to * rate_to) / (k1 + k2);
  const double peak = std::sqrt(std::max(peak2, 0.0));
  if (peak >= std::max(r0, rate_to) && dist > kTiny) {
    const double r = std::min(peak, cruise_rate_);
    if (k1 * (r - r0) > 1e-6) profile_.ramp(r, k1 * (r - r0));
    const double cruise = u_to - profile_.u_end() - 0.5 * k2 * (r * r - rate_to * rate_to);
    if (cruise / r > 1e-6) profile_.hold(cruise / r);
    if (k2 * (r - rate_to) > 1e-6) profile_.ramp(rate_to, k2 * (r - rate_to));
  } else if (std::abs(rate_to - r0) > kTiny) {
    // No room for the planned ramps: one harder ramp straight to the target rate.
    const double seconds = dist > kTiny ? 2.0 * dist / (r0 + rate_to) : 0.2;
    profile_.ramp(rate_to, seconds);
  }
}

void RealisticMotion::make_waves() {
  const double step_w = kTwoPi * rng_.uniform(p_.step_min_hz, p_.step_max_hz);
  const double ph = rng_.uniform(0.0, kTwoPi);
  // Bob: height at the step frequency, roll and yaw sway at the stride frequency (one
  // left-right cycle per two steps), pitch nod at the step frequency.
  position_waves_.push_back({2, p_.bob_m, step_w, ph});
  angle_waves_.push_back({0, p_.bob_roll_rad, 0.5 * step_w, 0.5 * ph});
  angle_waves_.push_back({1, p_.bob_pitch_rad, step_w, ph + 1.2});
  angle_waves_.push_back({2, p_.bob_yaw_rad, 0.5 * step_w, 0.5 * ph + 1.5});
  for (int axis = 0; axis < 3; ++axis) {
    for (int j = 0; j < 2; ++j) {
      const double w = kTwoPi * rng_.uniform(p_.vibration_min_hz, p_.vibration_max_hz);
      const double amp_m = p_.vibration_mps2 * rng_.uniform(0.5, 1.0) / (w * w);
      position_waves_.push_back({axis, amp_m, w, rng_.uniform(0.0, kTwoPi)});
      const double wa = kTwoPi * rng_.uniform(p_.vibration_min_hz, p_.vibration_max_hz);
      const double amp_rad = p_.vibration_rps * rng_.uniform(0.5, 1.0) / wa;
      angle_waves_.push_back({axis, amp_rad, wa, rng_.uniform(0.0, kTwoPi)});
    }
  }
}

BodyState RealisticMotion::state(double t_s) const {
  const double t = std::clamp(t_s, 0.0, duration_s());
  const WarpPoint w = profile_.at(t);
  const PathPoint q = path_.path(w.u);
  BodyState st;
  st.t_s = t;
  st.p_w_m = q.p_w_m;
  st.v_w_mps = q.dp_du_m * w.du;
  st.a_w_mps2 = q.d2p_du2_m * (w.du * w.du) + q.dp_du_m * w.ddu;
  // Walking intensity g in [0, 1] and its derivatives scale the bob and the vibration.
  const double g = w.du / cruise_rate_, dg = w.ddu / cruise_rate_, ddg = w.dddu / cruise_rate_;
  for (const Wave& v : position_waves_) {
    const double s = std::sin(v.omega_rps * t + v.phase_rad);
    const double c = std::cos(v.omega_rps * t + v.phase_rad);
    const double om = v.omega_rps;
    st.p_w_m[v.axis] += v.amp * g * s;
    st.v_w_mps[v.axis] += v.amp * (dg * s + g * om * c);
    st.a_w_mps2[v.axis] += v.amp * (ddg * s + 2.0 * dg * om * c - g * om * om * s);
  }
  double angle[3] = {0, 0, 0}, rate[3] = {0, 0, 0};  // roll, pitch, yaw
  for (const Wave& v : angle_waves_) {
    const double s = std::sin(v.omega_rps * t + v.phase_rad);
    const double c = std::cos(v.omega_rps * t + v.phase_rad);
    angle[v.axis] += v.amp * g * s;
    rate[v.axis] += v.amp * (dg * s + g * v.omega_rps * c);
  }
  // Heading: quick turns at the corners, as a function of the path parameter.
  double yaw = yaw0_rad_, dyaw_du = 0.0;
  for (const Turn& tn : turns_) {
    const double tau = (w.u - (tn.center_u - tn.half_u)) / (2.0 * tn.half_u);
    yaw += tn.delta_rad * smoothstep(tau);
    dyaw_du += tn.delta_rad * smoothstep_slope(tau) / (2.0 * tn.half_u);
  }
  // The route's slow sway, as in the smooth profile.
  const TrajectoryParams& tp = path_.params();
  const double wp = kTwoPi * tp.pitch_hz, wr = kTwoPi * tp.roll_hz;
  EulerZyx e;
  e.yaw = yaw + angle[2];
  e.yaw_rate = dyaw_du * w.du + rate[2];
  e.pitch = tp.pitch_amp_rad * std::sin(wp * t) + angle[1];
  e.pitch_rate = tp.pitch_amp_rad * wp * std::cos(wp * t) + rate[1];
  e.roll = tp.roll_amp_rad * std::sin(wr * t + 1.0) + angle[0];
  e.roll_rate = tp.roll_amp_rad * wr * std::cos(wr * t + 1.0) + rate[0];
  set_attitude(e, st);
  return st;
}

}  // namespace vigs::sim
