#include <gtest/gtest.h>

#include <random>

#include "core/geometry/so3.hpp"
#include "eval/umeyama.hpp"

namespace vigs::eval {
namespace {

struct Synthetic {
  std::vector<Eigen::Vector3d> from, to;
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  double s;
};

Synthetic make_synthetic(double s, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  std::normal_distribution<double> n(0.0, noise > 0 ? noise : 1.0);
  Synthetic d;
  d.R = geometry::so3_exp<double>(Eigen::Vector3d(0.4, -1.1, 2.0));
  d.t = Eigen::Vector3d(3.0, -7.0, 0.5);
  d.s = s;
  for (int i = 0; i < 200; ++i) {
    Eigen::Vector3d x(u(rng), u(rng), u(rng));
    Eigen::Vector3d y = s * (d.R * x) + d.t;
    if (noise > 0) y += Eigen::Vector3d(n(rng), n(rng), n(rng));
    d.from.push_back(x);
    d.to.push_back(y);
  }
  return d;
}

TEST(Umeyama, Se3RecoversKnownRigidTransform) {
  const auto d = make_synthetic(1.0, 0.0, 1);
  const Sim3 a = umeyama_align(d.from, d.to, Alignment::kSe3);
  EXPECT_LT((a.R - d.R).norm(), 1e-9);
  EXPECT_LT((a.t - d.t).norm(), 1e-9);
  EXPECT_EQ(a.s, 1.0);
}

TEST(Umeyama, Sim3RecoversKnownScale) {
  const auto d = make_synthetic(2.7, 0.0, 2);
  const Sim3 a = umeyama_align(d.from, d.to, Alignment::kSim3);
  EXPECT_NEAR(a.s, 2.7, 1e-9);
  EXPECT_LT((a.R - d.R).norm(), 1e-9);
  EXPECT_LT((a.t - d.t).norm(), 1e-8);
  for (std::size_t i = 0; i < d.from.size(); ++i) {
    EXPECT_LT((a.apply(d.from[i]) - d.to[i]).norm(), 1e-8);
  }
}

TEST(Umeyama, Se3OnScaledDataKeepsUnitScaleAndLeavesResidual) {
  const auto d = make_synthetic(2.0, 0.0, 3);
  const Sim3 a = umeyama_align(d.from, d.to, Alignment::kSe3);
  EXPECT_EQ(a.s, 1.0);
  double worst = 0.0;
  for (std::size_t i = 0; i < d.from.size(); ++i) {
    worst = std::max(worst, (a.apply(d.from[i]) - d.to[i]).norm());
  }
  EXPECT_GT(worst, 1.0);                // a rigid fit cannot absorb a factor 2
  EXPECT_LT((a.R - d.R).norm(), 1e-9);  // but the rotation is still the right one
}

TEST(Umeyama, NoneIsIdentity) {
  const auto d = make_synthetic(1.0, 0.0, 4);
  const Sim3 a = umeyama_align(d.from, d.to, Alignment::kNone);
  EXPECT_EQ(a.R, Eigen::Matrix3d::Identity());
  EXPECT_EQ(a.t, Eigen::Vector3d::Zero());
}

TEST(Umeyama, NoisyDataStaysCloseAndReflectionIsNeverReturned) {
  const auto d = make_synthetic(0.5, 0.01, 5);
  const Sim3 a = umeyama_align(d.from, d.to, Alignment::kSim3);
  EXPECT_NEAR(a.s, 0.5, 2e-3);
  EXPECT_NEAR(a.R.determinant(), 1.0, 1e-12);
  // Mirrored data: the best proper rotation, never a reflection.
  std::vector<Eigen::Vector3d> mirrored = d.from;
  for (auto& p : mirrored) p.z() = -p.z();
  const Sim3 m = umeyama_align(d.from, mirrored, Alignment::kSe3);
  EXPECT_NEAR(m.R.determinant(), 1.0, 1e-12);
}

TEST(Umeyama, RejectsMismatchedOrTooFewPoints) {
  std::vector<Eigen::Vector3d> a(3, Eigen::Vector3d::Zero()), b(2, Eigen::Vector3d::Zero());
  EXPECT_THROW(umeyama_align(a, b, Alignment::kSe3), std::invalid_argument);
  EXPECT_THROW(umeyama_align(b, b, Alignment::kSe3), std::invalid_argument);
  EXPECT_THROW(parse_alignment("sim2"), std::invalid_argument);
  EXPECT_EQ(parse_alignment("sim3"), Alignment::kSim3);
}

}  // namespace
}  // namespace vigs::eval
