// GICP on synthetic clouds: Jacobian check, recovery of known transforms within the claimed
// basin, determinism, and the degenerate-plane verdict.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "synthetic_scene.hpp"
#include "tracking/covariance.hpp"
#include "tracking/gicp.hpp"

namespace vigs::tracking {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

struct Prepared {
  GaussianCloud cloud;
  KdTree tree;
};

void prepare(const std::vector<Eigen::Vector3f>& pts, Prepared& out,
             Regularization reg = Regularization::normalized_ellipse) {
  out.cloud.clear();
  out.cloud.points_m = pts;
  out.cloud.colors_rgb.assign(pts.size(), {0, 0, 0});
  out.tree.build(out.cloud.points_m);
  rt::WorkerTeam team(2);
  CovarianceSetting cs;
  cs.regularization = reg;
  estimate_covariances(out.tree, cs, team, out.cloud);
}

std::vector<Eigen::Vector3f> transformed(const std::vector<Eigen::Vector3f>& pts,
                                         const geometry::Pose& T) {
  std::vector<Eigen::Vector3f> out;
  for (const auto& p : pts) {
    out.push_back((T * p.cast<double>()).cast<float>());
  }
  return out;
}

TEST(GicpFactor, ResidualJacobianMatchesNumericDifferentiation) {
  const geometry::Pose T =
      geometry::make_pose(Eigen::Vector3d(0.2, -0.1, 0.3), Eigen::Vector3d(0.5, -0.2, 1.0));
  const Eigen::Vector3d p(0.7, -0.4, 2.1), q(1.0, 0.2, 2.5);
  const auto residual = [&](const Vector6d& xi) -> Eigen::Vector3d {
    return q - geometry::se3_exp_rot_trans(xi) * T * p;
  };
  const Eigen::Matrix<double, 3, 6> J = gicp_residual_jacobian(T * p);
  const double h = 1e-6;
  for (int k = 0; k < 6; ++k) {
    Vector6d d = Vector6d::Zero();
    d(k) = h;
    const Eigen::Vector3d numeric = (residual(d) - residual(-d)) / (2.0 * h);
    EXPECT_LT((numeric - J.col(k)).norm(), 1e-8) << "column " << k;
  }
}

TEST(GicpFactor, AccumulatedHessianAndGradientMatchTheCost) {
  const geometry::Pose T =
      geometry::make_pose(Eigen::Vector3d(-0.1, 0.25, 0.05), Eigen::Vector3d(0.1, 0.3, -0.4));
  const Eigen::Vector3d p(0.3, 0.9, 1.7), q(0.5, 1.1, 1.2);
  Eigen::Matrix3d A;
  A << 2.0, 0.3, 0.1, 0.3, 1.5, -0.2, 0.1, -0.2, 0.8;
  const Eigen::Matrix3d M = A.inverse();
  const auto cost = [&](const Vector6d& xi) {
    const Eigen::Vector3d r = q - geometry::se3_exp_rot_trans(xi) * T * p;
    return r.dot(M * r);
  };
  Matrix6d H = Matrix6d::Zero();
  Vector6d b = Vector6d::Zero();
  const Eigen::Vector3d y = T * p;
  accumulate_gicp_factor(y, q - y, M, RobustKernel::none, 1.0, H, b);
  const Eigen::Matrix<double, 3, 6> J = gicp_residual_jacobian(y);
  EXPECT_LT((H - J.transpose() * M * J).norm(), 1e-12);
  const double h = 1e-6;
  for (int k = 0; k < 6; ++k) {
    Vector6d d = Vector6d::Zero();
    d(k) = h;
    const double numeric = (cost(d) - cost(-d)) / (2.0 * h);
    EXPECT_NEAR(numeric, 2.0 * b(k), 1e-6) << "gradient " << k;
  }
}

struct BasinCase {
  double rot_deg;
  double trans_m;
};

class GicpBasin : public ::testing::TestWithParam<BasinCase> {};

// Claimed basin on this scene: initial errors up to 10 deg and 0.15 m.
TEST_P(GicpBasin, RecoversKnownTransform) {
  const auto pts = test::room_scene(6000);
  const geometry::Pose T_t_s_true =
      geometry::make_pose(Eigen::Vector3d(0.02, -0.05, 0.03), Eigen::Vector3d(0.08, -0.03, 0.05));
  Prepared target, source;
  prepare(pts, target);
  prepare(transformed(pts, T_t_s_true.inverse()), source);
  const BasinCase c = GetParam();
  const geometry::Pose perturb =
      geometry::make_pose(Eigen::Vector3d(1.0, -2.0, 1.5).normalized() * c.rot_deg * kDeg,
                          Eigen::Vector3d(-1.0, 1.0, 2.0).normalized() * c.trans_m);
  Gicp::Setting s;
  s.max_correspondence_distance_m = 0.5;
  s.max_iterations = 60;
  s.rotation_eps_deg = 1e-4;
  s.translation_eps_m = 1e-6;
  Gicp gicp(s);
  const GicpResult r =
      gicp.align(CloudTarget{&target.cloud, &target.tree}, source.cloud, perturb * T_t_s_true);
  const geometry::PoseError e = geometry::pose_error(T_t_s_true, r.T_t_s);
  EXPECT_LT(e.translation_m, 1e-4);
  EXPECT_LT(e.rotation_rad, 0.01 * kDeg);
  EXPECT_EQ(r.verdict, GicpVerdict::converged) << to_string(r.verdict);
  EXPECT_GT(r.inlier_ratio, 0.99);
}

INSTANTIATE_TEST_SUITE_P(Basin, GicpBasin,
                         ::testing::Values(BasinCase{0.0, 0.0}, BasinCase{1.0, 0.01},
                                           BasinCase{5.0, 0.05}, BasinCase{10.0, 0.15}));

// Two different samplings of the same room: near the optimum the nearest neighbours switch and
// the cost no longer falls with every step. With the default stopping rule (0.1 deg, 1 mm) the
// search must end within a handful of linearisations (Marquardt damping relative to H's
// diagonal, and a refused step within a few eps ends it) and still land on the transform.
TEST(Gicp, DifferentSamplingsConvergeInFewIterations) {
  const geometry::Pose T_t_s_true =
      geometry::make_pose(Eigen::Vector3d(0.02, -0.05, 0.03), Eigen::Vector3d(0.08, -0.03, 0.05));
  Prepared target, source;
  // Depth-camera-like noise on both: 4 mm per axis.
  std::mt19937 rng(3);
  std::normal_distribution<float> noise(0.0f, 0.004f);
  const auto noisy = [&](std::vector<Eigen::Vector3f> pts) {
    for (Eigen::Vector3f& p : pts) p += Eigen::Vector3f(noise(rng), noise(rng), noise(rng));
    return pts;
  };
  prepare(noisy(test::room_scene(20000, 7)), target);
  prepare(noisy(transformed(test::room_scene(20000, 11), T_t_s_true.inverse())), source);
  Gicp::Setting s;  // the defaults: eps 0.1 deg and 1 mm, 30 iterations
  s.max_correspondence_distance_m = 0.3;
  Gicp gicp(s);
  const geometry::Pose guess =
      geometry::make_pose(Eigen::Vector3d(0.0, 0.0, 2.0 * kDeg), Eigen::Vector3d(0.03, 0, 0)) *
      T_t_s_true;
  const GicpResult r = gicp.align(CloudTarget{&target.cloud, &target.tree}, source.cloud, guess);
  const geometry::PoseError e = geometry::pose_error(T_t_s_true, r.T_t_s);
  EXPECT_EQ(r.verdict, GicpVerdict::converged) << to_string(r.verdict);
  EXPECT_LE(r.iterations, 8);
  EXPECT_LT(e.translation_m, 0.005);
  EXPECT_LT(e.rotation_rad, 0.2 * kDeg);
}

TEST(Gicp, BitIdenticalRunToRunWithTwoThreads) {
  const auto pts = test::room_scene(4000);
  const geometry::Pose T =
      geometry::make_pose(Eigen::Vector3d(0.03, 0.01, -0.02), Eigen::Vector3d(0.05, 0.02, -0.04));
  Prepared target, source;
  prepare(pts, target);
  prepare(transformed(pts, T), source);
  Gicp::Setting s;
  s.num_threads = 2;
  Gicp a(s), b(s);
  const CloudTarget tgt{&target.cloud, &target.tree};
  const GicpResult ra = a.align(tgt, source.cloud, geometry::Pose::Identity());
  const GicpResult rb = b.align(tgt, source.cloud, geometry::Pose::Identity());
  const GicpResult rc = a.align(tgt, source.cloud, geometry::Pose::Identity());
  EXPECT_EQ(ra.T_t_s.matrix(), rb.T_t_s.matrix());
  EXPECT_EQ(ra.T_t_s.matrix(), rc.T_t_s.matrix());
  EXPECT_EQ(ra.information, rb.information);
  EXPECT_EQ(ra.iterations, rb.iterations);
}

TEST(Gicp, OneAndTwoThreadsAgree) {
  const auto pts = test::room_scene(4000);
  const geometry::Pose T =
      geometry::make_pose(Eigen::Vector3d(0.03, 0.01, -0.02), Eigen::Vector3d(0.05, 0.02, -0.04));
  Prepared target, source;
  prepare(pts, target);
  prepare(transformed(pts, T), source);
  Gicp::Setting s;
  s.num_threads = 1;
  Gicp one(s);
  s.num_threads = 2;
  Gicp two(s);
  const CloudTarget tgt{&target.cloud, &target.tree};
  const GicpResult r1 = one.align(tgt, source.cloud, geometry::Pose::Identity());
  const GicpResult r2 = two.align(tgt, source.cloud, geometry::Pose::Identity());
  const geometry::PoseError e = geometry::pose_error(r1.T_t_s, r2.T_t_s);
  EXPECT_LT(e.translation_m, 1e-9);
  EXPECT_LT(e.rotation_rad, 1e-9);
  EXPECT_EQ(r1.num_inliers, r2.num_inliers);
}

TEST(Gicp, SinglePlaneIsDegenerate) {
  const auto pts = test::plane_scene(4000);
  const geometry::Pose T =
      geometry::make_pose(Eigen::Vector3d(0.0, 0.0, 0.02), Eigen::Vector3d(0.03, 0.02, 0.01));
  for (const Regularization reg : {Regularization::normalized_ellipse, Regularization::plane}) {
    Prepared target, source;
    prepare(pts, target, reg);
    prepare(transformed(pts, T), source, reg);
    Gicp gicp;
    const GicpResult r = gicp.align(CloudTarget{&target.cloud, &target.tree}, source.cloud,
                                    geometry::Pose::Identity());
    std::printf("plane (%s): eigen ratio %.2e\n",
                reg == Regularization::plane ? "plane" : "normalized_ellipse", r.eigen_ratio);
    EXPECT_EQ(r.verdict, GicpVerdict::degenerate) << "eigen ratio " << r.eigen_ratio;
  }
}

TEST(Gicp, StructuredSceneIsNotDegenerate) {
  const auto pts = test::room_scene(4000);
  Prepared target;
  prepare(pts, target);
  Gicp gicp;
  const GicpResult r = gicp.align(CloudTarget{&target.cloud, &target.tree}, target.cloud,
                                  geometry::Pose::Identity());
  std::printf("room: eigen ratio %.2e\n", r.eigen_ratio);
  EXPECT_EQ(r.verdict, GicpVerdict::converged) << "eigen ratio " << r.eigen_ratio;
  EXPECT_GT(r.eigen_ratio, 1e-2);
}

TEST(Gicp, EmptySourceIsDivergedNotACrash) {
  const auto pts = test::room_scene(500);
  Prepared target;
  prepare(pts, target);
  Gicp gicp;
  const GicpResult r = gicp.align(CloudTarget{&target.cloud, &target.tree}, GaussianCloud{},
                                  geometry::Pose::Identity());
  EXPECT_EQ(r.verdict, GicpVerdict::diverged);
  EXPECT_EQ(r.inlier_ratio, 0.0);
  geometry::Pose nan_guess = geometry::Pose::Identity();
  nan_guess.translation().x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(gicp.align(CloudTarget{&target.cloud, &target.tree}, target.cloud, nan_guess).verdict,
            GicpVerdict::diverged);
}

}  // namespace
}  // namespace vigs::tracking
