#pragma once
// One GICP correspondence: residual, Jacobian and its Gauss–Newton contribution.
//
// T = T_t_s maps source points into the target frame. For a source point p (with covariance
// C_s) matched to target point q (covariance C_t), the residual is r = q - T p, weighted by
// M = (C_t + R C_s R^T)^-1. Increments are left-multiplicative in the target frame:
// T <- Exp(xi) T, xi = [w; v] (rotation first), Exp as geometry::se3_exp_rot_trans. With
// y = T p, r(xi) ~= r + [y]x w - v, so the Jacobian is J = [ [y]x, -I ].
#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>

#include "core/geometry/so3.hpp"

namespace vigs::tracking {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

enum class RobustKernel { none, huber, cauchy };

/// dr/dxi at y = T p (3x6).
inline Eigen::Matrix<double, 3, 6> gicp_residual_jacobian(const Eigen::Vector3d& y) {
  Eigen::Matrix<double, 3, 6> J;
  J.leftCols<3>() = geometry::hat<double>(y);
  J.rightCols<3>() = -Eigen::Matrix3d::Identity();
  return J;
}

/// Robust cost rho(e2) of a squared Mahalanobis distance and its IRLS weight d rho / d e2.
inline double robust_weight(RobustKernel kernel, double width, double e2, double& rho) {
  switch (kernel) {
    case RobustKernel::huber: {
      const double s = std::sqrt(e2);
      if (s <= width) {
        rho = e2;
        return 1.0;
      }
      rho = 2.0 * width * s - width * width;
      return width / s;
    }
    case RobustKernel::cauchy: {
      const double w2 = width * width;
      rho = w2 * std::log1p(e2 / w2);
      return 1.0 / (1.0 + e2 / w2);
    }
    case RobustKernel::none:
      break;
  }
  rho = e2;
  return 1.0;
}

/// Adds w J^T M J to H and w J^T M r to b (the cost gradient is 2b) and returns rho. `M` is the
/// combined information matrix (C_t + R C_s R^T)^-1. Exploits J's structure: no 3x6 products.
inline double accumulate_gicp_factor(const Eigen::Vector3d& y, const Eigen::Vector3d& r,
                                     const Eigen::Matrix3d& M, RobustKernel kernel, double width,
                                     Matrix6d& H, Vector6d& b) {
  const Eigen::Vector3d Mr = M * r;
  const double e2 = r.dot(Mr);
  double rho = 0.0;
  const double w = robust_weight(kernel, width, e2, rho);
  const Eigen::Matrix3d A = geometry::hat<double>(y);  // J = [A, -I], A^T = -A
  const Eigen::Matrix3d MA = M * A;
  // J^T M J = [A^T M A, -A^T M; -M A, M]
  H.topLeftCorner<3, 3>().noalias() -= w * (A * MA);
  H.topRightCorner<3, 3>().noalias() += w * (A * M);
  H.bottomLeftCorner<3, 3>().noalias() -= w * MA;
  H.bottomRightCorner<3, 3>().noalias() += w * M;
  // J^T M r = [A^T M r; -M r]
  b.head<3>().noalias() -= w * (A * Mr);
  b.tail<3>().noalias() -= w * Mr;
  return rho;
}

/// M = (C_t + R C_s R^T)^-1; false when the sum is not invertible.
inline bool gicp_information(const Eigen::Matrix3d& C_t, const Eigen::Matrix3d& R,
                             const Eigen::Matrix3d& C_s, Eigen::Matrix3d& M) {
  const Eigen::Matrix3d C = C_t + R * C_s * R.transpose();
  bool invertible = false;
  double det = 0.0;
  C.computeInverseAndDetWithCheck(M, det, invertible, 1e-30);
  return invertible && det > 0.0;
}

}  // namespace vigs::tracking
