// The keyframe pose graph: exact Jacobians (numeric check), the information of a GICP
// measurement in the residual's order, and a drifted loop pulled back by one loop edge.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "core/geometry/so3.hpp"
#include "tracking/pose_graph.hpp"

namespace vigs::tracking {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

geometry::Pose random_pose(std::mt19937& rng, double rot_rad, double trans_m) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  return geometry::make_pose(Eigen::Vector3d(u(rng), u(rng), u(rng)) * rot_rad,
                             Eigen::Vector3d(u(rng), u(rng), u(rng)) * trans_m);
}

TEST(PoseGraph, EdgeJacobiansMatchNumericDifferentiation) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 5; ++trial) {
    const geometry::Pose T_i = random_pose(rng, 1.0, 3.0);
    const geometry::Pose T_j = random_pose(rng, 1.0, 3.0);
    // A measurement away from T_i^-1 T_j: the residual is not zero where the check is made.
    const geometry::Pose Z = T_i.inverse() * T_j * random_pose(rng, 0.2, 0.3);
    Matrix6d J_i, J_j;
    PoseGraph::edge_jacobians(T_i, T_j, Z, J_i, J_j);
    ASSERT_GT(PoseGraph::residual(T_i, T_j, Z).norm(), 0.05);
    const double h = 1e-6;
    for (int k = 0; k < 6; ++k) {
      Vector6d d = Vector6d::Zero();
      d(k) = h;
      const Vector6d num_i = (PoseGraph::residual(PoseGraph::retract(T_i, d), T_j, Z) -
                              PoseGraph::residual(PoseGraph::retract(T_i, -d), T_j, Z)) /
                             (2.0 * h);
      const Vector6d num_j = (PoseGraph::residual(T_i, PoseGraph::retract(T_j, d), Z) -
                              PoseGraph::residual(T_i, PoseGraph::retract(T_j, -d), Z)) /
                             (2.0 * h);
      EXPECT_LT((num_i - J_i.col(k)).norm(), 1e-6) << "trial " << trial << " node i col " << k;
      EXPECT_LT((num_j - J_j.col(k)).norm(), 1e-6) << "trial " << trial << " node j col " << k;
    }
  }
}

TEST(PoseGraph, LeftIncrementInformationIsTheResidualsToFirstOrder) {
  // A measurement perturbed on the left by xi (GICP's convention: rotation and translation
  // applied apart) moves the residual by r = M^-1 xi; the information must transform so that
  // xi^T L_xi xi = r^T L_r r for any small xi.
  std::mt19937 rng(5);
  const geometry::Pose Z = random_pose(rng, 0.8, 2.0);
  Matrix6d A = Matrix6d::Random();
  const Matrix6d L_xi = A * A.transpose() + Matrix6d::Identity();
  const Matrix6d L_r = information_of_left_increment(L_xi, Z);
  for (int trial = 0; trial < 4; ++trial) {
    const Vector6d xi = Vector6d::Random() * 1e-5;
    geometry::Pose Zp = Z;
    const Eigen::Matrix3d R_xi = geometry::so3_exp<double>(xi.head<3>());
    Zp.linear() = R_xi * Z.linear();
    Zp.translation() = R_xi * Z.translation() + xi.tail<3>();
    // T_i = I, T_j = Z, measurement Zp.
    const Vector6d r = PoseGraph::residual(geometry::Pose::Identity(), Z, Zp);
    const double a = xi.dot(L_xi * xi);
    const double b = r.dot(L_r * r);
    EXPECT_NEAR(b / a, 1.0, 1e-3) << "trial " << trial;
  }
}

TEST(PoseGraph, OneLoopEdgePullsADriftedSquareBackTowardsTheTruth) {
  // A 10 m square walked in 40 steps; the odometry turns 0.2 degrees too far at every step
  // (a gyro bias or a map's yaw drift) and overshoots 1 cm. The loop edge says the last node
  // is where the first is.
  const int n = 40;
  std::vector<geometry::Pose> truth;
  geometry::Pose T = geometry::Pose::Identity();
  for (int k = 0; k <= n; ++k) {
    truth.push_back(T);
    const double turn = (k % 10 == 9) ? 90.0 * kDeg : 0.0;
    T = T * geometry::make_pose(Eigen::Vector3d(0, turn, 0), Eigen::Vector3d(0, 0, 1.0));
  }
  PoseGraph g;
  geometry::Pose est = truth[0];
  g.add_node(est);
  for (int k = 1; k <= n; ++k) {
    const geometry::Pose step = truth[k - 1].inverse() * truth[k];
    const geometry::Pose drifted =
        step * geometry::make_pose(Eigen::Vector3d(0, 0.2 * kDeg, 0), Eigen::Vector3d(0, 0, 0.01));
    est = est * drifted;
    g.add_node(est);
    PoseGraphEdge e;
    e.i = k - 1;
    e.j = k;
    e.T_i_j = drifted;
    e.information = (Vector6d() << 1e4, 1e4, 1e4, 1e2, 1e2, 1e2).finished().asDiagonal();
    g.add_edge(e);
  }
  const auto error = [&](int k) {
    return (g.pose(k).translation() - truth[static_cast<std::size_t>(k)].translation()).norm();
  };
  double before = 0.0;
  for (int k = 0; k <= n; ++k) before = std::max(before, error(k));
  ASSERT_GT(before, 0.5);  // the drift this test must remove

  // Without a loop the odometry is already the optimum.
  const PoseGraphResult open = g.optimize();
  EXPECT_LT(open.final_cost, 1e-9);
  EXPECT_NEAR(error(n), (est.translation() - truth[n].translation()).norm(), 1e-9);

  PoseGraphEdge loop;
  loop.i = 0;
  loop.j = n;
  loop.T_i_j = truth[0].inverse() * truth[n];
  loop.information = (Vector6d() << 1e6, 1e6, 1e6, 1e4, 1e4, 1e4).finished().asDiagonal();
  g.add_edge(loop);
  const PoseGraphResult closed = g.optimize();
  EXPECT_LT(closed.final_cost, closed.initial_cost);
  double after = 0.0;
  for (int k = 0; k <= n; ++k) after = std::max(after, error(k));
  EXPECT_LT(error(n), 0.02);
  EXPECT_LT(after, 0.25 * before) << "before " << before << " m, after " << after << " m";
  EXPECT_TRUE(g.pose(0).isApprox(truth[0])) << "node 0 is held";
}

TEST(PoseGraph, RefusesEdgesItCannotUse) {
  PoseGraph g;
  g.add_node(geometry::Pose::Identity());
  g.add_node(geometry::Pose::Identity());
  PoseGraphEdge e;
  e.i = 0;
  e.j = 2;
  EXPECT_THROW(g.add_edge(e), std::invalid_argument);
  e.j = 0;
  EXPECT_THROW(g.add_edge(e), std::invalid_argument);
  e.j = 1;
  e.information(3, 3) = -1.0;
  EXPECT_THROW(g.add_edge(e), std::invalid_argument);
  e.information = Matrix6d::Identity();
  e.information(0, 1) = std::nan("");
  EXPECT_THROW(g.add_edge(e), std::invalid_argument);
  e.information = Matrix6d::Identity();
  EXPECT_NO_THROW(g.add_edge(e));
  EXPECT_EQ(g.num_edges(), 1u);
}

}  // namespace
}  // namespace vigs::tracking
