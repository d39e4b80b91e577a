// The GICP pose prior (tracking/pose_prior.hpp): its Jacobian against central differences,
// the Geman-McClure weight against the derivative of its cost, and GICP with a prior on a
// degenerate scene (a single plane): the unconstrained directions follow the prior, the
// constrained ones the geometry.
#include <gtest/gtest.h>

#include <cmath>

#include "rt/worker_team.hpp"
#include "tests/tracking/synthetic_scene.hpp"
#include "tracking/covariance.hpp"
#include "tracking/gicp.hpp"
#include "tracking/kdtree.hpp"

namespace vigs::tracking {
namespace {

using geometry::Pose;

TEST(PosePrior, JacobianMatchesCentralDifferences) {
  const Pose T_mean =
      geometry::make_pose(Eigen::Vector3d(0.3, -0.2, 0.5), Eigen::Vector3d(12.0, -4.0, 1.5));
  // A pose some way from the mean, so Jl^-1 and [rho]x matter.
  const Pose T =
      geometry::make_pose(Eigen::Vector3d(0.05, 0.08, -0.04), Eigen::Vector3d(0.2, 0.1, -0.3)) *
      T_mean;
  const Vector6d e = pose_prior_residual(T, T_mean);
  const Matrix6d J = pose_prior_jacobian(e);
  constexpr double h = 1e-6;
  for (int c = 0; c < 6; ++c) {
    Vector6d xi = Vector6d::Zero();
    xi(c) = h;
    const Vector6d plus = pose_prior_residual(geometry::se3_exp_rot_trans(xi) * T, T_mean);
    const Vector6d minus = pose_prior_residual(geometry::se3_exp_rot_trans(-xi) * T, T_mean);
    const Vector6d numeric = (plus - minus) / (2.0 * h);
    SCOPED_TRACE(c);
    EXPECT_LT((numeric - J.col(c)).norm(), 1e-7) << numeric.transpose();
  }
  // e is the increment that maps the mean onto T.
  EXPECT_TRUE((geometry::se3_exp_rot_trans(e) * T_mean).isApprox(T, 1e-12));
}

TEST(RobustKernel, GemanMcClureWeightIsTheDerivativeOfItsCostAndBounded) {
  constexpr double w = 0.5, h = 1e-7;
  for (const double e2 : {0.01, 0.2, 1.0, 7.0, 100.0}) {
    double rho = 0.0, rp = 0.0, rm = 0.0;
    const double weight = robust_weight(RobustKernel::geman_mcclure, w, e2, rho);
    robust_weight(RobustKernel::geman_mcclure, w, e2 + h, rp);
    robust_weight(RobustKernel::geman_mcclure, w, e2 - h, rm);
    EXPECT_NEAR(weight, (rp - rm) / (2 * h), 1e-6) << e2;
    EXPECT_LT(rho, w * w);  // a gross outlier costs at most w^2
  }
}

GaussianCloud cloud_of(const std::vector<Eigen::Vector3f>& pts, KdTree& tree) {
  GaussianCloud c;
  c.points_m = pts;
  c.cov_raw_m2.resize(pts.size());
  c.cov_m2.resize(pts.size());
  c.colors_rgb.resize(pts.size());
  tree.build(c.points_m);
  rt::WorkerTeam team(1);
  estimate_covariances(tree, CovarianceSetting{}, team, c);
  return c;
}

TEST(GicpWithPrior, PlaneConstrainsItsNormalAndThePriorTheRest) {
  KdTree tree_t, tree_s;
  const GaussianCloud target = cloud_of(test::plane_scene(4000, 3), tree_t);
  const GaussianCloud source = cloud_of(test::plane_scene(4000, 9), tree_s);
  const CloudTarget tgt{&target, &tree_t, nullptr};
  // Truth: identity. Prior mean: off by 5 cm in x (in the plane) and 2 cm in z (its normal).
  PosePrior prior;
  prior.T_mean = geometry::make_pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.05, 0.0, 0.02));
  prior.information = Matrix6d::Identity() * 1e2;
  Gicp::Setting s;
  s.num_threads = 1;
  Gicp gicp(s);
  const GicpResult with = gicp.align(tgt, source, prior.T_mean, &prior);
  EXPECT_TRUE(with.prior_used);
  EXPECT_GT(with.degenerate_directions, 0);  // GICP alone: 3 weak directions
  EXPECT_EQ(with.verdict, GicpVerdict::degenerate);
  // Normal (z) from the geometry, in-plane (x) from the prior.
  EXPECT_LT(std::abs(with.T_t_s.translation().z()), 2e-3);
  EXPECT_NEAR(with.T_t_s.translation().x(), 0.05, 2e-3);
  // The posterior information is the data's plus the prior's.
  EXPECT_GT((with.information_posterior - with.information).diagonal().minCoeff(), 50.0);
  // Weakest direction of the data is an in-plane one: no z translation in it.
  EXPECT_LT(std::abs(with.weakest_direction(5)), 0.1);
}

}  // namespace
}  // namespace vigs::tracking
