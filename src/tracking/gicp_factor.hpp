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

#include "core/config/tracking_components.hpp"
#include "core/geometry/so3.hpp"

namespace vigs::tracking {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

/// Robust kernels on the squared Mahalanobis distance e2 = r^T M r, width w on sqrt(e2):
/// huber (linear beyond w), cauchy (w^2 log(1 + e2/w^2)) and geman_mcclure
/// (w^2 e2 / (w^2 + e2): bounded, so a gross outlier such as a walking person's point matched to
/// the wall behind it adds at most w^2 to the cost and almost nothing to the system).
/// (Declared with the settings: config/tracking_components.hpp.)
using config::RobustKernel;

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
    case RobustKernel::geman_mcclure: {
      const double w2 = width * width;
      const double d = w2 + e2;
      rho = w2 * e2 / d;
      return (w2 * w2) / (d * d);
    }
    case RobustKernel::none:
      break;
  }
  rho = e2;
  return 1.0;
}

/// Sums of the Gauss–Newton system over correspondences, kept compact: the 21 entries of the
/// symmetric H's upper triangle and b, written out for J = [A, -I] with A = [y]x, so a factor
/// costs about a third of the dense 6x6 products.
struct GicpSystem {
  double h[21] = {};  ///< upper triangle of H, row by row
  double b[6] = {};
  double cost = 0.0;

  /// Adds w J^T M J to H and w J^T M r to b (the cost gradient is 2b) and rho to the cost;
  /// M = (C_t + R C_s R^T)^-1 is symmetric (its lower triangle is not read).
  void add(const Eigen::Vector3d& y, const Eigen::Vector3d& r, const Eigen::Matrix3d& M,
           RobustKernel kernel, double width) {
    const double m00 = M(0, 0), m01 = M(0, 1), m02 = M(0, 2), m11 = M(1, 1), m12 = M(1, 2),
                 m22 = M(2, 2);
    const double Mr0 = m00 * r(0) + m01 * r(1) + m02 * r(2);
    const double Mr1 = m01 * r(0) + m11 * r(1) + m12 * r(2);
    const double Mr2 = m02 * r(0) + m12 * r(1) + m22 * r(2);
    const double e2 = r(0) * Mr0 + r(1) * Mr1 + r(2) * Mr2;
    double rho = 0.0;
    const double w = robust_weight(kernel, width, e2, rho);
    cost += rho;
    const double x = y(0), yy = y(1), z = y(2);
    // AM = [y]x M, row by row: [0 -z y; z 0 -x; -y x 0] M.
    const double a00 = -z * m01 + yy * m02, a01 = -z * m11 + yy * m12, a02 = -z * m12 + yy * m22;
    const double a10 = z * m00 - x * m02, a11 = z * m01 - x * m12, a12 = z * m02 - x * m22;
    const double a20 = -yy * m00 + x * m01, a21 = -yy * m01 + x * m11, a22 = -yy * m02 + x * m12;
    // H_rr = A^T M A = -(AM) A; columns of A: (0, z, -y), (-z, 0, x), (y, -x, 0).
    h[0] -= w * (a01 * z - a02 * yy);
    h[1] -= w * (-a00 * z + a02 * x);
    h[2] -= w * (a00 * yy - a01 * x);
    h[6] -= w * (-a10 * z + a12 * x);
    h[7] -= w * (a10 * yy - a11 * x);
    h[11] -= w * (a20 * yy - a21 * x);
    // H_rt = A M (top-right block, full).
    h[3] += w * a00;
    h[4] += w * a01;
    h[5] += w * a02;
    h[8] += w * a10;
    h[9] += w * a11;
    h[10] += w * a12;
    h[12] += w * a20;
    h[13] += w * a21;
    h[14] += w * a22;
    // H_tt = M.
    h[15] += w * m00;
    h[16] += w * m01;
    h[17] += w * m02;
    h[18] += w * m11;
    h[19] += w * m12;
    h[20] += w * m22;
    // b_r = A^T M r = -A (M r), b_t = -M r.
    b[0] -= w * (-z * Mr1 + yy * Mr2);
    b[1] -= w * (z * Mr0 - x * Mr2);
    b[2] -= w * (-yy * Mr0 + x * Mr1);
    b[3] -= w * Mr0;
    b[4] -= w * Mr1;
    b[5] -= w * Mr2;
  }

  GicpSystem& operator+=(const GicpSystem& o) {
    for (int i = 0; i < 21; ++i) h[i] += o.h[i];
    for (int i = 0; i < 6; ++i) b[i] += o.b[i];
    cost += o.cost;
    return *this;
  }

  /// Adds the sums to dense H (both triangles) and b.
  void add_to(Matrix6d& H, Vector6d& bv) const {
    int k = 0;
    for (int r = 0; r < 6; ++r) {
      for (int c = r; c < 6; ++c, ++k) {
        H(r, c) += h[k];
        if (c != r) H(c, r) += h[k];
      }
      bv(r) += b[r];
    }
  }
};

/// Adds w J^T M J to H and w J^T M r to b (the cost gradient is 2b) and returns rho. `M` is the
/// combined information matrix (C_t + R C_s R^T)^-1.
inline double accumulate_gicp_factor(const Eigen::Vector3d& y, const Eigen::Vector3d& r,
                                     const Eigen::Matrix3d& M, RobustKernel kernel, double width,
                                     Matrix6d& H, Vector6d& b) {
  GicpSystem sys;
  sys.add(y, r, M, kernel, width);
  sys.add_to(H, b);
  return sys.cost;
}

/// M = (C_t + R C_s R^T)^-1 for symmetric C_t, C_s; false when the sum is not positive
/// definite enough to invert (determinant <= 1e-30). Uses the symmetry: 6 entries of the sum,
/// 6 cofactors.
inline bool gicp_information(const Eigen::Matrix3d& C_t, const Eigen::Matrix3d& R,
                             const Eigen::Matrix3d& C_s, Eigen::Matrix3d& M) {
  const Eigen::Matrix3d RC = R * C_s;
  // C = C_t + RC R^T, upper triangle.
  const double c00 = C_t(0, 0) + RC.row(0).dot(R.row(0));
  const double c01 = C_t(0, 1) + RC.row(0).dot(R.row(1));
  const double c02 = C_t(0, 2) + RC.row(0).dot(R.row(2));
  const double c11 = C_t(1, 1) + RC.row(1).dot(R.row(1));
  const double c12 = C_t(1, 2) + RC.row(1).dot(R.row(2));
  const double c22 = C_t(2, 2) + RC.row(2).dot(R.row(2));
  const double k00 = c11 * c22 - c12 * c12;
  const double k01 = c02 * c12 - c01 * c22;
  const double k02 = c01 * c12 - c02 * c11;
  const double det = c00 * k00 + c01 * k01 + c02 * k02;
  if (!(det > 1e-30)) {
    return false;
  }
  const double inv = 1.0 / det;
  const double k11 = c00 * c22 - c02 * c02;
  const double k12 = c01 * c02 - c00 * c12;
  const double k22 = c00 * c11 - c01 * c01;
  M << k00 * inv, k01 * inv, k02 * inv,  //
      k01 * inv, k11 * inv, k12 * inv,   //
      k02 * inv, k12 * inv, k22 * inv;
  return true;
}

}  // namespace vigs::tracking
