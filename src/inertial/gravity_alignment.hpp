#pragma once
// Initial attitude from the accelerometer at rest: the world frame of the initial guess is
// z-up (gravity (0, 0, -g)), so the first tracked pose must be gravity-aligned. At rest the
// IMU measures f_b = R_w_b^T (0, 0, g); the smallest rotation taking f_b's direction onto +z
// gives R_w_b with zero yaw (yaw is unobservable from gravity).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <span>

#include "core/geometry/so3.hpp"
#include "core/types/imu_sample.hpp"

namespace vigs::inertial {

/// R_w_b from a specific-force direction measured at rest; nullopt for a near-zero vector.
inline std::optional<Eigen::Matrix3d> gravity_aligned_R_w_b(const Eigen::Vector3d& f_b_mps2) {
  if (!(f_b_mps2.norm() > 1e-3)) return std::nullopt;
  return Eigen::Quaterniond::FromTwoVectors(f_b_mps2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

/// Same, from samples taken with the position at rest, in the body frame at `t_ref_ns` (the
/// first camera frame). The attitude may still sway during the window (a hand-held or legged
/// carrier never holds perfectly still): each reading is first rotated into the body frame at
/// t_ref by the gyro, R_ref_i = prod Exp(w dt) from the sample nearest t_ref, so a rotation of
/// a few tenths of a degree over the window does not tilt the mean. The gyro bias is unknown
/// here; its effect over a window of under a second is negligible next to the sway it removes.
inline std::optional<Eigen::Matrix3d> gravity_aligned_R_w_b(std::span<const ImuSample> at_rest,
                                                            std::int64_t t_ref_ns) {
  if (at_rest.empty()) return std::nullopt;
  const auto gyro = [](const ImuSample& s) {
    return Eigen::Vector3d(s.gyro_rps[0], s.gyro_rps[1], s.gyro_rps[2]);
  };
  const auto accel = [](const ImuSample& s) {
    return Eigen::Vector3d(s.accel_mps2[0], s.accel_mps2[1], s.accel_mps2[2]);
  };
  const auto distance_ns = [&](std::size_t j) {
    return at_rest[j].t_ns > t_ref_ns ? at_rest[j].t_ns - t_ref_ns : t_ref_ns - at_rest[j].t_ns;
  };
  std::size_t k = 0;  // the sample nearest t_ref
  for (std::size_t i = 1; i < at_rest.size(); ++i) {
    if (distance_ns(i) < distance_ns(k)) k = i;
  }
  const auto dt_s = [&](std::size_t a, std::size_t b) {
    return 1e-9 * static_cast<double>(at_rest[b].t_ns - at_rest[a].t_ns);
  };
  Eigen::Vector3d sum = accel(at_rest[k]);
  Eigen::Matrix3d R_ref_i = Eigen::Matrix3d::Identity();
  for (std::size_t i = k + 1; i < at_rest.size(); ++i) {
    const Eigen::Vector3d w = 0.5 * (gyro(at_rest[i - 1]) + gyro(at_rest[i]));
    R_ref_i = R_ref_i * geometry::so3_exp<double>(Eigen::Vector3d(w * dt_s(i - 1, i)));
    sum += R_ref_i * accel(at_rest[i]);
  }
  R_ref_i.setIdentity();
  for (std::size_t i = k; i-- > 0;) {
    const Eigen::Vector3d w = 0.5 * (gyro(at_rest[i]) + gyro(at_rest[i + 1]));
    R_ref_i = R_ref_i * geometry::so3_exp<double>(Eigen::Vector3d(-w * dt_s(i, i + 1)));
    sum += R_ref_i * accel(at_rest[i]);
  }
  return gravity_aligned_R_w_b(Eigen::Vector3d(sum / static_cast<double>(at_rest.size())));
}

}  // namespace vigs::inertial
