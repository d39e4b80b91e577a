// The covariance regularisation (Eigen's closed-form computeDirect inside) against its
// definition evaluated with Eigen's iterative SelfAdjointEigenSolver, over random symmetric
// matrices: generic, planar, near-double roots, and scales from 1e-6 to 1 m^2; and the
// degenerate neighbourhoods (line, single point, isotropic).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>

#include "tracking/covariance.hpp"

namespace vigs::tracking {
namespace {

struct Case {
  Eigen::Matrix3d U;
  Eigen::Vector3d l;  // ascending
  Eigen::Matrix3d A;
};

Case random_case(std::mt19937& rng, const Eigen::Vector3d& shape, double scale) {
  std::normal_distribution<double> n(0.0, 1.0);
  Case c;
  c.U = Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
  c.l = shape * scale;
  c.A = c.U * c.l.asDiagonal() * c.U.transpose();
  c.A = (0.5 * (c.A + c.A.transpose())).eval();
  return c;
}

std::vector<Eigen::Vector3d> shapes() {
  return {{0.2, 0.5, 1.0},   {1e-4, 0.3, 1.0},           {0.0, 0.4, 1.0}, {1e-6, 1e-6, 1.0},
          {0.0, 0.0, 1.0},   {0.5, 0.5 + 1e-9, 1.0},     {0.1, 1.0, 1.0}, {1.0, 1.0, 1.0},
          {1e-3, 2e-3, 1.0}, {0.3, 0.3000001, 0.3000002}};
}

Eigen::Matrix3d reference_regularization(const Case& c, Regularization mode, double eps) {
  Eigen::Vector3d values;
  if (mode == Regularization::plane) {
    values = Eigen::Vector3d(eps, 1.0, 1.0);
  } else {
    values = (c.l / c.l(1)).cwiseMax(eps);
  }
  return c.U * values.asDiagonal() * c.U.transpose();
}

TEST(Covariance, FastRegularisationMatchesTheDefinition) {
  std::mt19937 rng(5);
  CovarianceSetting s;
  for (const Regularization mode : {Regularization::plane, Regularization::normalized_ellipse}) {
    s.regularization = mode;
    for (const Eigen::Vector3d& shape : shapes()) {
      // The plane's normal is undefined when the two smallest eigenvalues coincide, and the
      // ellipse of a line (l1 = 0) is the identity by definition: checked separately.
      if (shape(1) - shape(0) < 1e-3 || shape(1) == 0.0) continue;
      for (const double scale : {1e-6, 1e-3, 1.0}) {
        for (int rep = 0; rep < 50; ++rep) {
          const Case c = random_case(rng, shape, scale);
          const Eigen::Matrix3f got = regularize_covariance(c.A.cast<float>(), s);
          // The reference from the float input, as the function sees it.
          const Eigen::Matrix3d A = c.A.cast<float>().cast<double>();
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A);
          Case ref{eig.eigenvectors(), eig.eigenvalues(), A};
          const Eigen::Matrix3d want = reference_regularization(ref, mode, s.epsilon);
          EXPECT_LE((got.cast<double>() - want).cwiseAbs().maxCoeff(), 1e-4 * want.norm())
              << "shape " << shape.transpose() << " scale " << scale;
        }
      }
    }
  }
}

TEST(Covariance, DegenerateNeighbourhoods) {
  CovarianceSetting s;
  s.regularization = Regularization::normalized_ellipse;
  // A line (l0 = l1 = 0) and a single repeated point: identity, as documented.
  EXPECT_TRUE(regularize_covariance(Eigen::Vector3f(0, 0, 1).asDiagonal(), s).isIdentity());
  EXPECT_TRUE(regularize_covariance(Eigen::Matrix3f::Zero(), s).isIdentity());
  // Isotropic: the ellipse is the identity, the plane has eigenvalues (eps, 1, 1).
  EXPECT_TRUE(regularize_covariance(2e-4f * Eigen::Matrix3f::Identity(), s).isIdentity(1e-6f));
  s.regularization = Regularization::plane;
  const Eigen::Matrix3f p = regularize_covariance(2e-4f * Eigen::Matrix3f::Identity(), s);
  const Eigen::Vector3f ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f>(p).eigenvalues();
  EXPECT_NEAR(ev(0), 1e-3f, 1e-6f);
  EXPECT_NEAR(ev(1), 1.0f, 1e-6f);
  EXPECT_NEAR(ev(2), 1.0f, 1e-6f);
  // A line with a plane model: the normal lies anywhere orthogonal to the line.
  const Eigen::Matrix3f q = regularize_covariance(Eigen::Vector3f(0, 0, 1).asDiagonal(), s);
  EXPECT_NEAR(q(2, 2), 1.0f, 1e-6f);
}

}  // namespace
}  // namespace vigs::tracking
