#pragma once
// A Gaussian prior on the pose GICP estimates, as one more factor of its least squares: the
// IMU-predicted camera pose with its covariance (fused tracking, tracking.fusion: fused).
//
// Parameterisation (the GICP increment's, gicp_factor.hpp): a pose T is written relative to the
// prior's mean T_p as T = Exp(e) T_p with Exp = geometry::se3_exp_rot_trans, e = [phi; rho]:
//   R = Exp(phi) R_p,  t = Exp(phi) t_p + rho   =>   phi = Log(R R_p^T),  rho = t - R R_p^T t_p.
// The prior's cost is e^T Lambda e (Lambda = the inverse covariance of e: rotation in rad,
// translation in m, about the world origin, rotation first).
//
// Under GICP's left increment T <- Exp(xi) T, xi = [w; v]:
//   phi' = Log(Exp(w) Exp(phi))  ~ phi + Jl^-1(phi) w
//   rho' = Exp(w) rho + v        ~ rho - [rho]x w + v
// so de/dxi = [[Jl^-1(phi), 0], [-[rho]x, I]] (checked by central differences in
// tests/tracking/test_pose_prior.cpp).
#include "core/geometry/se3.hpp"
#include "tracking/gicp_factor.hpp"

namespace vigs::tracking {

struct PosePrior {
  geometry::Pose T_mean = geometry::Pose::Identity();  ///< T_p (for the tracker: T_w_c)
  Matrix6d information = Matrix6d::Zero();             ///< Lambda, of e = [phi; rho]
};

/// e(T) relative to the prior's mean.
inline Vector6d pose_prior_residual(const geometry::Pose& T, const geometry::Pose& T_mean) {
  const Eigen::Matrix3d dR = T.linear() * T_mean.linear().transpose();
  Vector6d e;
  e.head<3>() = geometry::so3_log<double>(dR);
  e.tail<3>() = T.translation() - dR * T_mean.translation();
  return e;
}

/// de/dxi at e (see the header comment).
inline Matrix6d pose_prior_jacobian(const Vector6d& e) {
  Matrix6d J = Matrix6d::Zero();
  // Jl^-1(phi) = Jr^-1(-phi).
  J.topLeftCorner<3, 3>() = geometry::so3_right_jacobian_inv<double>(Eigen::Vector3d(-e.head<3>()));
  J.bottomLeftCorner<3, 3>() = -geometry::hat<double>(Eigen::Vector3d(e.tail<3>()));
  J.bottomRightCorner<3, 3>().setIdentity();
  return J;
}

/// Adds the prior's Gauss–Newton terms at T to H and b (same conventions as GicpSystem: the
/// cost gradient is 2b) and returns its cost e^T Lambda e.
inline double add_pose_prior(const PosePrior& prior, const geometry::Pose& T, Matrix6d& H,
                             Vector6d& b) {
  const Vector6d e = pose_prior_residual(T, prior.T_mean);
  const Matrix6d J = pose_prior_jacobian(e);
  const Matrix6d JtL = J.transpose() * prior.information;
  H += JtL * J;
  b += JtL * e;
  return e.dot(prior.information * e);
}

}  // namespace vigs::tracking
