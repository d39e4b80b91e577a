#pragma once
// Closed-form integrals of the SO(3) exponential used by the exact zero-order-hold step, and
// their derivatives. With K = hat(phi), theta = |phi|:
//   first integral   L(phi) = int_0^1 Exp(s phi) ds              = I   + c1 K + c2 K^2
//                    (the left Jacobian), c1 = (1-cos)/theta^2,  c2 = (theta-sin)/theta^3
//   second integral  Q(phi) = int_0^1 int_0^s Exp(u phi) du ds   = I/2 + c1 K + c2 K^2
//                    c1 = (theta-sin)/theta^3,  c2 = (theta^2/2 + cos - 1)/theta^4
// so that over a step of dt with constant rate w and specific force a (phi = w dt):
//   int_0^dt Exp(w s) a ds = dt L(phi) a   and the double integral is dt^2 Q(phi) a.
// Below theta = 0.2 the coefficients come from their Taylor series, which are exact to
// rounding there and avoid the cancellation of the closed forms.
#include <Eigen/Core>
#include <cmath>

#include "core/geometry/so3.hpp"

namespace vigs::inertial {

/// M(phi) = c0 I + c1(theta) K + c2(theta) K^2 applied to a vector, with d(M a)/dphi.
struct So3Series {
  double c0 = 1.0, c1 = 0.0, c2 = 0.0;
  double dc1 = 0.0, dc2 = 0.0;  ///< c1'(theta)/theta and c2'(theta)/theta

  [[nodiscard]] Eigen::Matrix3d matrix(const Eigen::Vector3d& phi) const {
    const Eigen::Matrix3d K = geometry::hat<double>(phi);
    return c0 * Eigen::Matrix3d::Identity() + c1 * K + c2 * K * K;
  }
  [[nodiscard]] Eigen::Vector3d apply(const Eigen::Vector3d& phi, const Eigen::Vector3d& a) const {
    const Eigen::Vector3d ka = phi.cross(a);
    return c0 * a + c1 * ka + c2 * phi.cross(ka);
  }
  /// d(M(phi) a)/dphi.
  [[nodiscard]] Eigen::Matrix3d derivative(const Eigen::Vector3d& phi,
                                           const Eigen::Vector3d& a) const {
    const Eigen::Vector3d ka = phi.cross(a);
    const Eigen::Vector3d kka = phi.cross(ka);
    // d(K a)/dphi = -hat(a);  d(K^2 a)/dphi = phi a^T + (phi.a) I - 2 a phi^T.
    Eigen::Matrix3d d = -c1 * geometry::hat<double>(a) +
                        c2 * (phi * a.transpose() + phi.dot(a) * Eigen::Matrix3d::Identity() -
                              2.0 * a * phi.transpose());
    d += (dc1 * ka + dc2 * kka) * phi.transpose();
    return d;
  }
};

constexpr double kSo3SeriesThreshold = 0.2;

/// L(phi), the first integral (left Jacobian of SO(3)).
inline So3Series so3_first_integral(const Eigen::Vector3d& phi) {
  const double t2 = phi.squaredNorm();
  So3Series s;
  s.c0 = 1.0;
  if (t2 < kSo3SeriesThreshold * kSo3SeriesThreshold) {
    const double t4 = t2 * t2, t6 = t4 * t2;
    s.c1 = 0.5 - t2 / 24.0 + t4 / 720.0 - t6 / 40320.0;
    s.c2 = 1.0 / 6.0 - t2 / 120.0 + t4 / 5040.0 - t6 / 362880.0;
    s.dc1 = -1.0 / 12.0 + t2 / 180.0 - t4 / 6720.0;
    s.dc2 = -1.0 / 60.0 + t2 / 1260.0 - t4 / 60480.0;
  } else {
    const double t = std::sqrt(t2), sn = std::sin(t), cs = std::cos(t);
    s.c1 = (1.0 - cs) / t2;
    s.c2 = (t - sn) / (t2 * t);
    s.dc1 = sn / (t2 * t) - 2.0 * (1.0 - cs) / (t2 * t2);
    s.dc2 = (1.0 - cs) / (t2 * t2) - 3.0 * (t - sn) / (t2 * t2 * t);
  }
  return s;
}

/// Q(phi), the second integral.
inline So3Series so3_second_integral(const Eigen::Vector3d& phi) {
  const double t2 = phi.squaredNorm();
  So3Series s;
  s.c0 = 0.5;
  if (t2 < kSo3SeriesThreshold * kSo3SeriesThreshold) {
    const double t4 = t2 * t2, t6 = t4 * t2;
    s.c1 = 1.0 / 6.0 - t2 / 120.0 + t4 / 5040.0 - t6 / 362880.0;
    s.c2 = 1.0 / 24.0 - t2 / 720.0 + t4 / 40320.0 - t6 / 3628800.0;
    s.dc1 = -1.0 / 60.0 + t2 / 1260.0 - t4 / 60480.0;
    s.dc2 = -1.0 / 360.0 + t2 / 10080.0 - t4 / 604800.0;
  } else {
    const double t = std::sqrt(t2), sn = std::sin(t), cs = std::cos(t);
    const double t3 = t2 * t, t4 = t2 * t2;
    s.c1 = (t - sn) / t3;
    s.c2 = (0.5 * t2 + cs - 1.0) / t4;
    s.dc1 = (1.0 - cs) / t4 - 3.0 * (t - sn) / (t4 * t);
    s.dc2 = (t - sn) / (t4 * t) - 4.0 * (0.5 * t2 + cs - 1.0) / (t4 * t2);
  }
  return s;
}

}  // namespace vigs::inertial
