#pragma once
// Navigation state of the body (IMU) frame in a gravity-aligned world, and its prediction
// from preintegrated increments (Forster et al. TRO 2017, eq. 33):
//   R_j = R_i dR,  v_j = v_i + g dt + R_i dv,  p_j = p_i + v_i dt + g dt^2 / 2 + R_i dp.
#include <Eigen/Core>

#include "core/geometry/se3.hpp"
#include "inertial/preintegrator.hpp"

namespace vigs::inertial {

struct NavState {
  Eigen::Matrix3d R_w_b = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_w_b_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_w_b_mps = Eigen::Vector3d::Zero();

  [[nodiscard]] geometry::Pose T_w_b() const {
    geometry::Pose T = geometry::Pose::Identity();
    T.linear() = R_w_b;
    T.translation() = p_w_b_m;
    return T;
  }
};

/// Gravity in a z-up world, m/s^2.
inline Eigen::Vector3d gravity_w(double gravity_mps2) {
  return {0.0, 0.0, -gravity_mps2};
}

inline NavState predict_nav_state(const NavState& s, const DeltaState& d,
                                  const Eigen::Vector3d& g_w_mps2) {
  NavState out;
  out.R_w_b = s.R_w_b * d.R;
  out.v_w_b_mps = s.v_w_b_mps + g_w_mps2 * d.dt_s + s.R_w_b * d.v_mps;
  out.p_w_b_m =
      s.p_w_b_m + s.v_w_b_mps * d.dt_s + 0.5 * g_w_mps2 * d.dt_s * d.dt_s + s.R_w_b * d.p_m;
  return out;
}

/// Body motion from state i to state j: T_bi_bj = T_w_bi^-1 T_w_bj.
inline geometry::Pose relative_body_motion(const NavState& i, const NavState& j) {
  geometry::Pose T = geometry::Pose::Identity();
  T.linear() = i.R_w_b.transpose() * j.R_w_b;
  T.translation() = i.R_w_b.transpose() * (j.p_w_b_m - i.p_w_b_m);
  return T;
}

}  // namespace vigs::inertial
