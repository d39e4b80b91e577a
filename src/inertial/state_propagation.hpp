#pragma once
// Error-state algebra of the fused IMU/GICP estimator (tracking.fusion: fused): a 17-state
// error x = [dtheta, dp, dv, dbg, dba, dg] of the body state (R, p, v), the two biases and the
// direction of gravity in the world (map) frame, with the rotation error on the LEFT in the
// world frame (R = Exp(dtheta) R_hat) and additive errors otherwise, propagated over one
// preintegrated interval and updated from a camera pose.
//
// Gravity: g = Exp([dg; 0]) g_hat, a tilt about the world x and y axes (a turn about z does not
// move a vertical g; for the small tilts here the z part stays a gauge). The world is the
// tracker's map, fixed by the first keyframe's gravity-aligned pose: when that alignment or the
// map's later drift tilts it against the true vertical, GICP holds the body to the tilted map
// and the accelerometer sees g sin(tilt) sideways. Without this state only the accelerometer
// bias, a body-frame vector, can absorb it, and after the next 90 deg turn it points the wrong
// way (BENCHMARKS.md, sixteenth session). The tilt is world-fixed: turns separate it from the
// bias. Its prior sigma 0 pins it (the 15-state filter).
//
// Prediction over [i, j] (nav_state.hpp, Forster et al. eq. 33) at the filter's biases, with
// the preintegration's right rotation error dphi (dR_true = dR Exp(dphi)) and its bias Jacobians:
//   dtheta_j = dtheta_i + R_j (J_Rg dbg + dphi)                                  (R_j = R_i dR)
//   dv_j     = dv_i - [R_i dv]x dtheta_i + R_i (J_vg dbg + J_va dba + ddv) - dt [g]x dg
//   dp_j     = dp_i + dt dv_i - [R_i dp]x dtheta_i + R_i (J_pg dbg + J_pa dba + ddp)
//              - dt^2/2 [g]x dg
//   dbg_j = dbg_i, dba_j = dba_i, dg_j = dg_i (plus their random walks).
// x_j = Phi x_i + G n, n = [dphi, ddv, ddp] with the preintegration covariance.
//
// A camera pose T_w_c = T_w_b T_b_c perturbed as the tracker's pose prior is
// (tracking/pose_prior.hpp: T = Exp(e) T_hat, e = [phi; rho] about the world origin) shares the
// body's world twist: e = [dtheta; dp + [p_b]x dtheta] (camera_pose_jacobian). Every Jacobian
// here is checked by central differences in tests/inertial/test_state_propagation.cpp.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <limits>

#include "core/geometry/so3.hpp"
#include "inertial/nav_state.hpp"
#include "inertial/preintegrator.hpp"

namespace vigs::inertial {

inline constexpr int kStateDim = 17;  ///< [dtheta, dp, dv, dbg, dba] 15, gravity tilt 2
inline constexpr int kGravityRow = 15;
using MatS = Eigen::Matrix<double, kStateDim, kStateDim>;
using MatSx9 = Eigen::Matrix<double, kStateDim, 9>;
using Mat6xS = Eigen::Matrix<double, 6, kStateDim>;
using MatSx6 = Eigen::Matrix<double, kStateDim, 6>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using VecS = Eigen::Matrix<double, kStateDim, 1>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

/// Phi and G of the prediction from state `s_i` over the interval `pi` (whose linearisation
/// biases are the filter's, so the increments need no bias correction) with gravity `g_w`.
inline void prediction_jacobians(const NavState& s_i, const Preintegrator& pi,
                                 const Eigen::Vector3d& g_w, MatS& Phi, MatSx9& G) {
  const DeltaState d = pi.delta();
  const Eigen::Matrix3d& R = s_i.R_w_b;
  const Eigen::Matrix3d Rj = R * d.R;
  Phi.setIdentity();
  G.setZero();
  // rows: 0 dtheta, 3 dp, 6 dv, 9 dbg, 12 dba, 15 dg (x, y)
  Phi.block<3, 3>(0, 9) = Rj * pi.dR_dbg();
  Phi.block<3, 3>(3, 0) = -geometry::hat<double>(Eigen::Vector3d(R * d.p_m));
  Phi.block<3, 3>(3, 6) = d.dt_s * Eigen::Matrix3d::Identity();
  Phi.block<3, 3>(3, 9) = R * pi.dp_dbg();
  Phi.block<3, 3>(3, 12) = R * pi.dp_dba();
  Phi.block<3, 3>(6, 0) = -geometry::hat<double>(Eigen::Vector3d(R * d.v_mps));
  Phi.block<3, 3>(6, 9) = R * pi.dv_dbg();
  Phi.block<3, 3>(6, 12) = R * pi.dv_dba();
  const Eigen::Matrix<double, 3, 2> dg_dtilt = -geometry::hat<double>(g_w).leftCols<2>();
  Phi.block<3, 2>(6, kGravityRow) = d.dt_s * dg_dtilt;
  Phi.block<3, 2>(3, kGravityRow) = 0.5 * d.dt_s * d.dt_s * dg_dtilt;
  // noise columns: 0 dphi, 3 ddv, 6 ddp (the preintegrator's order)
  G.block<3, 3>(0, 0) = Rj;
  G.block<3, 3>(6, 3) = R;
  G.block<3, 3>(3, 6) = R;
}

/// de/dx of the camera pose (e about the world origin, rotation first) for body position p_b.
inline Mat6xS camera_pose_jacobian(const Eigen::Vector3d& p_w_b) {
  Mat6xS J = Mat6xS::Zero();
  J.block<3, 3>(0, 0).setIdentity();
  J.block<3, 3>(3, 0) = geometry::hat<double>(p_w_b);
  J.block<3, 3>(3, 3).setIdentity();
  return J;
}

/// Kalman update from a fused pose: the caller's estimate minimised GICP's cost plus the prior
/// (mean at J x = 0, covariance P_pose = J P J^T); `e_star` is its e relative to the prior's
/// mean and `Y` its posterior information (prior + GICP). Since the pose estimate equals the
/// conditional mean given GICP's measurement, the whole state moves by
///   dx = P J^T P_pose^-1 e*,  P+ = P - P J^T S^-1 J P,  S^-1 = (P_pose + H_gicp^-1)^-1
///                                                        = L - L Y^-1 L  (L = P_pose^-1),
/// which never inverts GICP's own (possibly singular) information. Returns false (nothing
/// changed) when P_pose or Y is not positive definite.
inline bool fused_pose_update(const Mat6xS& J, const Vec6& e_star, const Mat6& Y, MatS& P,
                              VecS& dx) {
  const MatSx6 PJt = P * J.transpose();
  const Mat6 P_pose = J * PJt;
  const Eigen::LLT<Mat6> llt_p(P_pose);
  const Eigen::LLT<Mat6> llt_y(Y);
  if (llt_p.info() != Eigen::Success || llt_y.info() != Eigen::Success) return false;
  const Mat6 L = llt_p.solve(Mat6::Identity());
  const Mat6 S_inv = L - L * llt_y.solve(L);
  dx = PJt * (L * e_star);
  MatS P_new = P - PJt * S_inv * PJt.transpose();
  P = 0.5 * (P_new + P_new.transpose());
  return dx.allFinite() && P.allFinite();
}

/// Zero-velocity update: the measurement 0 = v + n, n ~ N(0, sigma^2 I), of a body the IMU
/// shows at rest (stillness_detector.hpp), applied to the state error with covariance P whose
/// current velocity estimate is `v_w_mps`. H = [0 0 I 0 ...], so
///   S = P_vv + sigma^2 I,  K = P H^T S^-1,  dx = K (0 - v),  P+ = P - K H P,
/// and through P's correlations it moves the pose and the biases too. `mahalanobis` gets
/// v^T S^-1 v; above `gate` (a moving body that reads as still) nothing is applied. Returns
/// whether P and dx were updated (false too when S is not positive definite or the result is
/// not finite).
inline bool zero_velocity_update(const Eigen::Vector3d& v_w_mps, double sigma_mps, double gate,
                                 MatS& P, VecS& dx, double& mahalanobis) {
  const Eigen::Matrix<double, kStateDim, 3> PHt = P.middleCols<3>(6);
  const Eigen::Matrix3d S =
      P.block<3, 3>(6, 6) + sigma_mps * sigma_mps * Eigen::Matrix3d::Identity();
  const Eigen::LLT<Eigen::Matrix3d> llt(S);
  mahalanobis = std::numeric_limits<double>::infinity();
  if (llt.info() != Eigen::Success) return false;
  const Eigen::Vector3d S_inv_v = llt.solve(v_w_mps);
  mahalanobis = v_w_mps.dot(S_inv_v);
  if (!(mahalanobis <= gate)) return false;
  const VecS dx_new = -PHt * S_inv_v;
  const MatS P_new = P - PHt * llt.solve(PHt.transpose());
  if (!dx_new.allFinite() || !P_new.allFinite()) return false;
  dx = dx_new;
  P = 0.5 * (P_new + P_new.transpose());
  return true;
}

}  // namespace vigs::inertial
