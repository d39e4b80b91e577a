#include <gtest/gtest.h>

#include <random>

#include "core/geometry/body_from_camera.hpp"
#include "core/geometry/se3.hpp"
#include "core/geometry/so3.hpp"
#include "core/types/pinhole_camera.hpp"

namespace vigs::geometry {
namespace {

Eigen::Vector3d random_vec(std::mt19937& rng, double scale) {
  std::normal_distribution<double> n(0.0, scale);
  return {n(rng), n(rng), n(rng)};
}

// The robot file's R_b_c is row-major: the default maps the camera's optical axis (z) to the
// body's forward axis (x) and the camera's right (x) to the body's -y; read as column-major it
// would map z to -y.
TEST(BodyFromCamera, ReadsTheRowMajorRotationAndTheLeverArm) {
  config::ExtrinsicsSettings e;
  e.t_b_c_m = {0.1, 0.05, -0.02};
  const Pose T_b_c = body_from_camera(e);
  EXPECT_TRUE((T_b_c.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitX()));
  EXPECT_TRUE((T_b_c.linear() * Eigen::Vector3d::UnitX()).isApprox(-Eigen::Vector3d::UnitY()));
  EXPECT_TRUE(T_b_c.translation().isApprox(Eigen::Vector3d(0.1, 0.05, -0.02)));
  // a point 2 m ahead of the camera is 2 m ahead of the camera's origin in the body frame
  EXPECT_TRUE((T_b_c * Eigen::Vector3d(0, 0, 2)).isApprox(Eigen::Vector3d(2.1, 0.05, -0.02)));
}

TEST(So3, ExpLogRoundTripIncludingSmallAndNearPi) {
  std::mt19937 rng(1);
  for (double scale : {1e-9, 1e-4, 0.3, 1.5}) {
    for (int i = 0; i < 100; ++i) {
      Eigen::Vector3d phi = random_vec(rng, scale);
      if (phi.norm() > 3.1) phi *= 3.1 / phi.norm();
      EXPECT_LT((so3_log<double>(so3_exp<double>(phi)) - phi).norm(), 1e-9) << phi.transpose();
    }
  }
  const Eigen::Vector3d near_pi = Eigen::Vector3d(0.3, -0.5, 0.8).normalized() * (M_PI - 1e-6);
  EXPECT_LT((so3_log<double>(so3_exp<double>(near_pi)) - near_pi).norm(), 1e-6);
}

TEST(So3, RightJacobianMatchesNumericDerivative) {
  std::mt19937 rng(2);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Vector3d phi = random_vec(rng, 0.8);
    const Eigen::Matrix3d Jr = so3_right_jacobian<double>(phi);
    Eigen::Matrix3d numeric;
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d d = Eigen::Vector3d::Zero();
      d[k] = h;
      // Exp(phi)^-1 Exp(phi + d) = Exp(Jr d)
      numeric.col(k) =
          so3_log<double>(so3_exp<double>(phi).transpose() * so3_exp<double>(phi + d)) / h;
    }
    EXPECT_LT((Jr - numeric).norm(), 1e-5);
    EXPECT_LT((so3_right_jacobian_inv<double>(phi) * Jr - Eigen::Matrix3d::Identity()).norm(),
              1e-9);
  }
}

TEST(Se3, InterpolateGoesLinearlyAndBySlerpBetweenTheEnds) {
  const Pose a = make_pose(Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(1, 2, 3));
  const Pose b = make_pose(Eigen::Vector3d(0.5, 0.4, -0.3), Eigen::Vector3d(-1, 0, 5));
  EXPECT_LT(pose_error(interpolate(a, b, 0.0), a).translation_m, 1e-12);
  EXPECT_LT(pose_error(interpolate(a, b, 0.0), a).rotation_rad, 1e-9);
  EXPECT_LT(pose_error(interpolate(a, b, 1.0), b).translation_m, 1e-12);
  EXPECT_LT(pose_error(interpolate(a, b, 1.0), b).rotation_rad, 1e-9);
  const Pose m = interpolate(a, b, 0.25);
  EXPECT_LT((m.translation() - Eigen::Vector3d(0.5, 1.5, 3.5)).norm(), 1e-12);
  // On the geodesic: a quarter of the relative rotation's angle from a, the rest to b.
  const double whole = rotation_angle(a.linear().transpose() * b.linear());
  EXPECT_NEAR(rotation_angle(a.linear().transpose() * m.linear()), 0.25 * whole, 1e-9);
  EXPECT_NEAR(rotation_angle(m.linear().transpose() * b.linear()), 0.75 * whole, 1e-9);
}

TEST(Se3, PoseErrorAndCameraModel) {
  const Pose A = make_pose(Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(1, 2, 3));
  const Pose B = A * make_pose(Eigen::Vector3d(0, 0, 0.05), Eigen::Vector3d(0.01, 0, 0));
  const auto e = pose_error(A, B);
  EXPECT_NEAR(e.translation_m, 0.01, 1e-12);
  EXPECT_NEAR(e.rotation_rad, 0.05, 1e-12);
  const PinholeCamera cam{720, 480, 415.0, 415.0, 360.0, 240.0};
  const Eigen::Vector3d p = cam.back_project(100.5, 300.25, 2.5);
  EXPECT_LT((cam.project(p) - Eigen::Vector2d(100.5, 300.25)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(p.z(), 2.5);
}

}  // namespace
}  // namespace vigs::geometry
