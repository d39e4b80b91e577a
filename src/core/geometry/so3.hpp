#pragma once
// SO(3) on Eigen: hat/vee, exponential and logarithm maps, right Jacobian and its inverse.
// Conventions: rotation vectors in radians; R = Exp(phi); the right Jacobian Jr satisfies
// Exp(phi + dphi) ~= Exp(phi) * Exp(Jr(phi) * dphi) (Forster et al., TRO 2017, eq. 8).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace vigs::geometry {

template <class S>
using Mat3 = Eigen::Matrix<S, 3, 3>;
template <class S>
using Vec3 = Eigen::Matrix<S, 3, 1>;

/// Skew-symmetric matrix: hat(a) * b == a.cross(b).
template <class S>
Mat3<S> hat(const Vec3<S>& v) {
  Mat3<S> m;
  m << S(0), -v.z(), v.y(), v.z(), S(0), -v.x(), -v.y(), v.x(), S(0);
  return m;
}

template <class S>
Vec3<S> vee(const Mat3<S>& m) {
  return Vec3<S>(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1)) * S(0.5);
}

/// Exp: rotation vector -> rotation matrix (Rodrigues), Taylor-expanded near zero.
template <class S>
Mat3<S> so3_exp(const Vec3<S>& phi) {
  const S theta2 = phi.squaredNorm();
  const Mat3<S> K = hat(phi);
  if (theta2 < S(1e-10)) {
    return Mat3<S>::Identity() + K + S(0.5) * K * K;
  }
  const S theta = std::sqrt(theta2);
  return Mat3<S>::Identity() + (std::sin(theta) / theta) * K +
         ((S(1) - std::cos(theta)) / theta2) * K * K;
}

/// Log: rotation matrix -> rotation vector in [0, pi], robust near 0 and pi.
template <class S>
Vec3<S> so3_log(const Mat3<S>& R) {
  const Eigen::AngleAxis<S> aa(R);
  return aa.axis() * aa.angle();
}

/// Right Jacobian of SO(3).
template <class S>
Mat3<S> so3_right_jacobian(const Vec3<S>& phi) {
  const S theta2 = phi.squaredNorm();
  const Mat3<S> K = hat(phi);
  if (theta2 < S(1e-10)) {
    return Mat3<S>::Identity() - S(0.5) * K + (S(1) / S(6)) * K * K;
  }
  const S theta = std::sqrt(theta2);
  return Mat3<S>::Identity() - ((S(1) - std::cos(theta)) / theta2) * K +
         ((theta - std::sin(theta)) / (theta2 * theta)) * K * K;
}

/// Inverse of the right Jacobian of SO(3).
template <class S>
Mat3<S> so3_right_jacobian_inv(const Vec3<S>& phi) {
  const S theta2 = phi.squaredNorm();
  const Mat3<S> K = hat(phi);
  if (theta2 < S(1e-10)) {
    return Mat3<S>::Identity() + S(0.5) * K + (S(1) / S(12)) * K * K;
  }
  const S theta = std::sqrt(theta2);
  return Mat3<S>::Identity() + S(0.5) * K +
         (S(1) / theta2 - (S(1) + std::cos(theta)) / (S(2) * theta * std::sin(theta))) * K * K;
}

/// Re-orthonormalise a rotation that accumulated rounding error.
template <class S>
Mat3<S> normalize_rotation(const Mat3<S>& R) {
  return Eigen::Quaternion<S>(R).normalized().toRotationMatrix();
}

}  // namespace vigs::geometry
