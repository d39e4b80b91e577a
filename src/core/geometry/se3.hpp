#pragma once
// SE(3) as Eigen::Isometry3d plus the few helpers the pipeline needs. Naming: T_a_b maps
// points from frame b into frame a (p_a = T_a_b * p_b); T_w_c is the camera pose in world.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "core/geometry/so3.hpp"

namespace vigs::geometry {

using Pose = Eigen::Isometry3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;

/// Pose from a rotation vector and translation.
inline Pose make_pose(const Eigen::Vector3d& rotvec, const Eigen::Vector3d& t) {
  Pose T = Pose::Identity();
  T.linear() = so3_exp<double>(rotvec);
  T.translation() = t;
  return T;
}

/// Pose from translation and unit quaternion (TUM order: tx ty tz qx qy qz qw).
inline Pose make_pose(const Eigen::Vector3d& t, const Eigen::Quaterniond& q) {
  Pose T = Pose::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = t;
  return T;
}

/// Left-multiplicative update used by the solvers: T <- Exp([w; v]) * T, with xi = [w; v]
/// (rotation first), the rotation applied about the origin of the target frame.
inline Pose se3_exp_rot_trans(const Vec6& xi) {
  return make_pose(Eigen::Vector3d(xi.head<3>()), Eigen::Vector3d(xi.tail<3>()));
}

/// The pose a fraction u of the way from a to b (u in [0, 1]): translation linearly, rotation
/// by slerp (the shorter arc). The one interpolation of poses in the project: recorded
/// trajectories between their samples, loop-closure corrections between keyframes.
inline Pose interpolate(const Pose& a, const Pose& b, double u) {
  const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
  return make_pose(Eigen::Vector3d((1.0 - u) * a.translation() + u * b.translation()),
                   qa.slerp(u, qb));
}

/// Rotation angle of R in radians.
inline double rotation_angle(const Eigen::Matrix3d& R) {
  return Eigen::AngleAxisd(R).angle();
}

/// Translation distance and rotation angle between two poses: |t(A^-1 B)|, angle(A^-1 B).
struct PoseError {
  double translation_m = 0.0;
  double rotation_rad = 0.0;
};
inline PoseError pose_error(const Pose& A, const Pose& B) {
  const Pose D = A.inverse() * B;
  return {D.translation().norm(), rotation_angle(D.linear())};
}

}  // namespace vigs::geometry
