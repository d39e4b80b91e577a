#include "sim/spline_trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace vigs::sim {
namespace {

/// Uniform cubic B-spline basis and its first two derivatives (w.r.t. the segment parameter).
void basis(double s, double b[4], double db[4], double ddb[4]) {
  const double s2 = s * s, s3 = s2 * s, m = 1.0 - s;
  b[0] = m * m * m / 6.0;
  b[1] = (3.0 * s3 - 6.0 * s2 + 4.0) / 6.0;
  b[2] = (-3.0 * s3 + 3.0 * s2 + 3.0 * s + 1.0) / 6.0;
  b[3] = s3 / 6.0;
  db[0] = -m * m / 2.0;
  db[1] = (3.0 * s2 - 4.0 * s) / 2.0;
  db[2] = (-3.0 * s2 + 2.0 * s + 1.0) / 2.0;
  db[3] = s2 / 2.0;
  ddb[0] = m;
  ddb[1] = 3.0 * s - 2.0;
  ddb[2] = -3.0 * s + 1.0;
  ddb[3] = s;
}

}  // namespace

SplineTrajectory::SplineTrajectory(const std::vector<Eigen::Vector2d>& route,
                                   const TrajectoryParams& p)
    : p_(p) {
  if (route.size() < 2) throw std::invalid_argument("trajectory: route needs >= 2 waypoints");
  const auto to3 = [&](const Eigen::Vector2d& q) {
    return Eigen::Vector3d(q.x(), q.y(), p.height_m);
  };
  const int still = std::max(0, static_cast<int>(std::lround(p.standstill_s / p.knot_interval_s)));
  still_knots_ = still;
  for (int k = 0; k < still + 3; ++k) ctrl_.push_back(to3(route.front()));
  for (std::size_t i = 0; i + 1 < route.size(); ++i) {
    const Eigen::Vector2d d = route[i + 1] - route[i];
    const double len = d.norm();
    if (len < 1e-9) throw std::invalid_argument("trajectory: repeated waypoint");
    const int n = std::max(1, static_cast<int>(std::ceil(len / p.spacing_m)));
    for (int k = 1; k <= n; ++k) ctrl_.push_back(to3(route[i] + d * (double(k) / n)));
  }
  for (int k = 0; k < 3; ++k) ctrl_.push_back(ctrl_.back());  // come to rest at the end
  // Heading control points: direction of the central difference, unwrapped; at rest, the
  // direction of the next motion.
  const std::size_t n = ctrl_.size();
  std::vector<double> yaw(n, 0.0);
  std::vector<bool> known(n, false);
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d d = ctrl_[std::min(k + 1, n - 1)] - ctrl_[k > 0 ? k - 1 : 0];
    if (d.head<2>().norm() > 1e-9) {
      yaw[k] = std::atan2(d.y(), d.x());
      known[k] = true;
    }
  }
  double last = 0.0;
  for (std::size_t k = 0; k < n; ++k) {  // the first known heading fills the start
    if (known[k]) {
      last = yaw[k];
      break;
    }
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (!known[k]) {
      yaw[k] = last;
    } else {
      double y = yaw[k];
      while (y - last > M_PI) y -= 2.0 * M_PI;
      while (y - last < -M_PI) y += 2.0 * M_PI;
      yaw[k] = y;
    }
    last = yaw[k];
  }
  yaw_ctrl_ = std::move(yaw);
  duration_s_ = static_cast<double>(n - 3) * p.knot_interval_s;
}

PathPoint SplineTrajectory::path(double u_in) const {
  const double u = std::clamp(u_in, 0.0, u_end());
  std::size_t i = static_cast<std::size_t>(std::floor(u));
  i = std::min(i, ctrl_.size() - 4);
  double b[4], db[4], ddb[4];
  basis(u - static_cast<double>(i), b, db, ddb);
  PathPoint out{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (int j = 0; j < 4; ++j) {
    out.p_w_m += b[j] * ctrl_[i + j];
    out.dp_du_m += db[j] * ctrl_[i + j];
    out.d2p_du2_m += ddb[j] * ctrl_[i + j];
  }
  return out;
}

BodyState SplineTrajectory::state(double t_s) const {
  const double t = std::clamp(t_s, 0.0, duration_s_);
  const double dt = p_.knot_interval_s;
  const double u = t / dt;
  std::size_t i = static_cast<std::size_t>(std::floor(u));
  i = std::min(i, ctrl_.size() - 4);
  const double s = u - static_cast<double>(i);
  double b[4], db[4], ddb[4];
  basis(s, b, db, ddb);
  BodyState st;
  st.t_s = t;
  st.p_w_m.setZero();
  st.v_w_mps.setZero();
  st.a_w_mps2.setZero();
  double yaw = 0.0, yaw_rate = 0.0;
  for (int j = 0; j < 4; ++j) {
    st.p_w_m += b[j] * ctrl_[i + j];
    st.v_w_mps += db[j] / dt * ctrl_[i + j];
    st.a_w_mps2 += ddb[j] / (dt * dt) * ctrl_[i + j];
    yaw += b[j] * yaw_ctrl_[i + j];
    yaw_rate += db[j] / dt * yaw_ctrl_[i + j];
  }
  const double wp = 2.0 * M_PI * p_.pitch_hz, wr = 2.0 * M_PI * p_.roll_hz;
  const double pitch = p_.pitch_amp_rad * std::sin(wp * t);
  const double pitch_rate = p_.pitch_amp_rad * wp * std::cos(wp * t);
  const double roll = p_.roll_amp_rad * std::sin(wr * t + 1.0);
  const double roll_rate = p_.roll_amp_rad * wr * std::cos(wr * t + 1.0);
  set_attitude({yaw, pitch, roll, yaw_rate, pitch_rate, roll_rate}, st);
  return st;
}

}  // namespace vigs::sim
