#pragma once
// Initial attitude from the accelerometer at rest: the world frame of the initial guess is
// z-up (gravity (0, 0, -g)), so the first tracked pose must be gravity-aligned. At rest the
// IMU measures f_b = R_w_b^T (0, 0, g); the smallest rotation taking f_b's direction onto +z
// gives R_w_b with zero yaw (yaw is unobservable from gravity).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <span>

#include "core/types/imu_sample.hpp"

namespace vigs::inertial {

/// R_w_b from a specific-force direction measured at rest; nullopt for a near-zero vector.
inline std::optional<Eigen::Matrix3d> gravity_aligned_R_w_b(const Eigen::Vector3d& f_b_mps2) {
  if (!(f_b_mps2.norm() > 1e-3)) return std::nullopt;
  return Eigen::Quaterniond::FromTwoVectors(f_b_mps2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

/// Same, from the mean accelerometer reading of samples taken at rest.
inline std::optional<Eigen::Matrix3d> gravity_aligned_R_w_b(std::span<const ImuSample> at_rest) {
  if (at_rest.empty()) return std::nullopt;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const ImuSample& s : at_rest) {
    sum += Eigen::Vector3d(s.accel_mps2[0], s.accel_mps2[1], s.accel_mps2[2]);
  }
  return gravity_aligned_R_w_b(Eigen::Vector3d(sum / static_cast<double>(at_rest.size())));
}

}  // namespace vigs::inertial
