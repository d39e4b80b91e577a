// Depth to points (counts, back-projection, voxel grid) and the kd-tree against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "tracking/covariance.hpp"
#include "tracking/depth_to_points.hpp"
#include "tracking/kdtree.hpp"

namespace vigs::tracking {
namespace {

TEST(DepthToPoints, SkipsAndCountsInvalidNearAndFarDepth) {
  const PinholeCamera cam{8, 4, 100.0, 100.0, 3.5, 1.5};
  ImageF32 depth(8, 4, 1, 2.0f);
  depth.at(0, 0) = std::numeric_limits<float>::quiet_NaN();
  depth.at(1, 0) = 0.0f;
  depth.at(2, 0) = -1.0f;
  depth.at(3, 0) = 0.05f;  // near
  depth.at(4, 0) = 9.0f;   // far
  ImageU8 rgb(8, 4, 3, 0);
  rgb.at(5, 1, 0) = 200;
  DepthToPoints::Setting s;
  s.pixel_stride = 1;
  s.near_m = 0.1;
  s.far_m = 8.0;
  DepthToPoints d2p(cam, s);
  GaussianCloud cloud;
  const DepthToPointsStats st = d2p.convert(depth, rgb, cloud);
  EXPECT_EQ(st.sampled, 32);
  EXPECT_EQ(st.invalid, 3);
  EXPECT_EQ(st.too_near, 1);
  EXPECT_EQ(st.too_far, 1);
  EXPECT_EQ(st.points, 27);
  ASSERT_EQ(cloud.size(), 27u);
  ASSERT_EQ(cloud.colors_rgb.size(), 27u);
  // Pixel (5, 1) at 2 m: x = (5 - 3.5) * 2 / 100, y = (1 - 1.5) * 2 / 100.
  const auto it = std::find_if(cloud.colors_rgb.begin(), cloud.colors_rgb.end(),
                               [](const auto& c) { return c[0] == 200; });
  ASSERT_NE(it, cloud.colors_rgb.end());
  const Eigen::Vector3f p = cloud.points_m[static_cast<std::size_t>(it - cloud.colors_rgb.begin())];
  EXPECT_NEAR(p.x(), 0.03f, 1e-6f);
  EXPECT_NEAR(p.y(), -0.01f, 1e-6f);
  EXPECT_NEAR(p.z(), 2.0f, 1e-6f);
}

TEST(DepthToPoints, StrideAndRawScaleAndVoxelGrid) {
  const PinholeCamera cam{64, 48, 50.0, 50.0, 31.5, 23.5};
  ImageU16 raw(64, 48, 1, 1500);  // 1.5 m in millimetres
  DepthToPoints::Setting s;
  s.pixel_stride = 4;
  DepthToPoints d2p(cam, s);
  GaussianCloud cloud;
  DepthToPointsStats st = d2p.convert(raw, 0.001, ImageU8{}, cloud);
  EXPECT_EQ(st.sampled, 16 * 12);
  EXPECT_EQ(st.points, 16 * 12);
  EXPECT_FLOAT_EQ(cloud.points_m[0].z(), 1.5f);
  s.voxel_size_m = 0.5;  // the 1.5 m plane spans ~1.9 x 1.4 m: a few voxels
  DepthToPoints voxel(cam, s);
  st = voxel.convert(raw, 0.001, ImageU8{}, cloud);
  EXPECT_LT(st.points, 30);
  EXPECT_GT(st.points, 3);
  for (const auto& p : cloud.points_m) {
    EXPECT_NEAR(p.z(), 1.5f, 1e-5f);
  }
}

TEST(DepthToPoints, MismatchedColourIsAnError) {
  const PinholeCamera cam{8, 4, 100.0, 100.0, 3.5, 1.5};
  DepthToPoints d2p(cam, {});
  GaussianCloud cloud;
  EXPECT_THROW(d2p.convert(ImageF32(8, 4, 1, 1.0f), ImageU8(4, 4, 3), cloud),
               std::invalid_argument);
  EXPECT_THROW(d2p.convert(ImageF32(9, 4, 1, 1.0f), ImageU8{}, cloud), std::invalid_argument);
}

TEST(KdTree, MatchesBruteForce) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Eigen::Vector3f> pts(3000);
  for (auto& p : pts) p = Eigen::Vector3f(u(rng), u(rng), 0.3f * u(rng));
  KdTree tree;
  tree.build(pts);
  for (int qi = 0; qi < 200; ++qi) {
    const Eigen::Vector3f q(u(rng), u(rng), u(rng));
    std::vector<std::pair<float, std::uint32_t>> all;
    for (std::uint32_t i = 0; i < pts.size(); ++i) all.emplace_back((pts[i] - q).squaredNorm(), i);
    std::sort(all.begin(), all.end());
    std::uint32_t idx[10];
    float d2[10];
    ASSERT_EQ(tree.knn(q, 10, idx, d2), 10);
    for (int j = 0; j < 10; ++j) {
      // Our leaf scan sums (dx^2 + dy^2) + dz^2; allow the last-bit difference to Eigen.
      EXPECT_FLOAT_EQ(d2[j], all[static_cast<std::size_t>(j)].first);
    }
    std::uint32_t ni = 0;
    float nd = 0.0f;
    const bool found = tree.nearest(q, 0.01f, ni, nd);
    EXPECT_EQ(found, all[0].first < 0.01f);
    if (found) {
      EXPECT_EQ(ni, all[0].second);
    }
    EXPECT_EQ(tree.point(all[0].second), pts[all[0].second]);
  }
}

TEST(KdTree, ParallelBuildGivesTheSameTree) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  std::vector<Eigen::Vector3f> pts(20000);
  for (auto& p : pts) p = Eigen::Vector3f(u(rng), u(rng), u(rng));
  KdTree serial, parallel;
  rt::WorkerTeam team(2);
  serial.build(pts);
  parallel.build(pts, &team);
  ASSERT_EQ(serial.leaf_order(), parallel.leaf_order());
  for (int q = 0; q < 500; ++q) {
    const Eigen::Vector3f query = pts[static_cast<std::size_t>(q) * 37];
    std::uint32_t ia[10], ib[10];
    float da[10], db[10];
    ASSERT_EQ(serial.knn(query, 10, ia, da), parallel.knn(query, 10, ib, db));
    for (int j = 0; j < 10; ++j) {
      EXPECT_EQ(ia[j], ib[j]);
      EXPECT_EQ(da[j], db[j]);
    }
  }
}

TEST(Covariance, RegularisationModes) {
  // A flat, elongated neighbourhood: eigenvalues 4, 1, 0.0001 (m^2) along x, y, z.
  const Eigen::Matrix3f raw = Eigen::Vector3f(4.0f, 1.0f, 1e-4f).asDiagonal();
  CovarianceSetting s;
  s.regularization = Regularization::normalized_ellipse;
  Eigen::Matrix3f c = regularize_covariance(raw, s);
  EXPECT_NEAR(c(0, 0), 4.0f, 1e-5f);  // l1 / l2
  EXPECT_NEAR(c(1, 1), 1.0f, 1e-5f);
  EXPECT_NEAR(c(2, 2), 1e-3f, 1e-7f);  // 1e-4 clamped up to epsilon
  s.regularization = Regularization::plane;
  c = regularize_covariance(raw, s);
  EXPECT_NEAR(c(0, 0), 1.0f, 1e-5f);
  EXPECT_NEAR(c(1, 1), 1.0f, 1e-5f);
  EXPECT_NEAR(c(2, 2), 1e-3f, 1e-7f);
  s.regularization = Regularization::none;
  EXPECT_EQ(regularize_covariance(raw, s), raw);
}

}  // namespace
}  // namespace vigs::tracking
