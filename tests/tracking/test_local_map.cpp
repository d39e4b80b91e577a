// Local map: nearest-neighbour correctness, flat memory over a 65 m x 65 m floor, eviction.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tracking/local_map.hpp"

namespace vigs::tracking {
namespace {

GaussianCloud random_cloud(int n, unsigned seed, float extent) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-extent, extent);
  GaussianCloud c;
  for (int i = 0; i < n; ++i) {
    c.points_m.emplace_back(u(rng), u(rng), 2.0f + u(rng));
    c.cov_m2.push_back(Eigen::Matrix3f::Identity());
    c.cov_raw_m2.push_back(Eigen::Matrix3f::Identity());
    c.colors_rgb.push_back({0, 0, 0});
  }
  return c;
}

TEST(LocalMap, NearestMatchesBruteForceWithinVoxelRadius) {
  LocalMap::Setting s;
  s.voxel_m = 0.1;
  s.points_per_voxel = 1000;  // keep every point, so brute force over the inserts is exact
  s.max_voxels = 8192;
  LocalMap map(s);
  const geometry::Pose T_w_c =
      geometry::make_pose(Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(1.0, 2.0, -0.5));
  const GaussianCloud c = random_cloud(3000, 5, 0.5f);
  map.insert(c, T_w_c);
  ASSERT_EQ(map.num_points(), 3000u);
  std::vector<Eigen::Vector3f> world;
  for (const auto& p : c.points_m) world.push_back((T_w_c * p.cast<double>()).cast<float>());
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-0.6f, 0.6f);
  for (int q = 0; q < 300; ++q) {
    const Eigen::Vector3f query =
        (T_w_c * Eigen::Vector3d(u(rng), u(rng), 2.0 + u(rng))).cast<float>();
    float best = 0.1f * 0.1f;
    bool any = false;
    for (const auto& w : world) {
      const float d2 = (w - query).squaredNorm();
      if (d2 < best) {
        best = d2;
        any = true;
      }
    }
    std::uint32_t idx = 0;
    float d2 = 0.0f;
    ASSERT_EQ(map.nearest(query, 0.1f * 0.1f, idx, d2), any);
    if (any) {
      EXPECT_NEAR(d2, best, 1e-6f);
      EXPECT_EQ((map.point(idx) - query).squaredNorm(), d2);
    }
  }
}

// A camera sweeping a 65 m x 65 m floor in rows 2 m apart, one keyframe per metre, each
// keyframe a 6 m x 6 m patch of floor and a wall ahead: the map stays within its bound and
// its buffers never grow, and nothing farther than the radius survives.
TEST(LocalMap, MemoryStaysFlatOver65By65MetreFloor) {
  LocalMap::Setting s;
  s.voxel_m = 0.1;
  s.points_per_voxel = 10;
  s.max_voxels = 8192;
  s.radius_m = 5.0;
  LocalMap map(s);
  const std::size_t bytes0 = map.memory_bytes();
  GaussianCloud patch;
  for (int i = 0; i < 60; ++i) {
    for (int j = 0; j < 60; ++j) {
      patch.points_m.emplace_back(-3.0f + 0.1f * i, 1.2f, 0.1f * j);  // floor, y down
      patch.cov_m2.push_back(Eigen::Matrix3f::Identity());
    }
  }
  for (int i = 0; i < 60; ++i) {
    for (int j = 0; j < 20; ++j) {
      patch.points_m.emplace_back(-3.0f + 0.1f * i, 1.2f - 0.1f * j, 6.0f);  // wall
      patch.cov_m2.push_back(Eigen::Matrix3f::Identity());
    }
  }
  std::size_t max_seen = 0;
  int keyframes = 0;
  for (int row = 0; row <= 32; ++row) {
    for (int step = 0; step <= 65; ++step) {
      const double x = row * 2.0;
      const double z = (row % 2 == 0) ? step : 65.0 - step;
      const geometry::Pose T_w_c =
          geometry::make_pose(Eigen::Vector3d(0.0, row % 2 == 0 ? 0.0 : 3.14159265358979, 0.0),
                              Eigen::Vector3d(x, 0.0, z));
      map.insert(patch, T_w_c);
      ++keyframes;
      max_seen = std::max(max_seen, map.num_points());
      ASSERT_LE(map.num_points(), map.max_points());
      ASSERT_LE(map.num_voxels(), static_cast<std::size_t>(s.max_voxels));
    }
  }
  EXPECT_EQ(keyframes, 33 * 66);
  EXPECT_EQ(map.memory_bytes(), bytes0);
  EXPECT_GT(max_seen, 10000u);
  // The last keyframe itself reaches beyond the radius until the next insertion evicts;
  // after an explicit eviction everything left is near the last camera position.
  const Eigen::Vector3f cam(64.0f, 0.0f, 65.0f);
  map.evict_far(cam.cast<double>());
  const float reach = static_cast<float>(s.radius_m + s.voxel_m);
  std::size_t checked = 0;
  for (float dx = -8.0f; dx <= 8.0f; dx += 0.5f) {
    for (float dz = -8.0f; dz <= 8.0f; dz += 0.5f) {
      const Eigen::Vector3f q = cam + Eigen::Vector3f(dx, 1.2f, dz);
      std::uint32_t idx = 0;
      float d2 = 0.0f;
      if (map.nearest(q, 0.01f, idx, d2)) {
        ++checked;
        EXPECT_LE((map.point(idx) - cam).norm(), reach);
      }
    }
  }
  EXPECT_GT(checked, 50u);
}

TEST(LocalMap, LeastRecentlySeenVoxelsGoFirstWhenFull) {
  LocalMap::Setting s;
  s.voxel_m = 0.1;
  s.points_per_voxel = 1;
  s.max_voxels = 256;
  s.radius_m = 1000.0;  // only the capacity bound acts
  LocalMap map(s);
  GaussianCloud c;
  for (int i = 0; i < 200; ++i) {
    c.points_m.emplace_back(0.1f * i + 0.05f, 0.05f, 0.05f);
    c.cov_m2.push_back(Eigen::Matrix3f::Identity());
  }
  map.insert(c, geometry::Pose::Identity());  // old keyframe at x in [0, 20)
  const geometry::Pose far =
      geometry::make_pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(100.0, 0.0, 0.0));
  map.insert(c, far);  // new keyframe needs 200 more voxels: old ones are evicted
  EXPECT_LE(map.num_voxels(), 256u);
  std::uint32_t idx = 0;
  float d2 = 0.0f;
  for (int i = 0; i < 200; ++i) {  // every new point is present
    ASSERT_TRUE(map.nearest(Eigen::Vector3f(100.05f + 0.1f * i, 0.05f, 0.05f), 1e-6f, idx, d2));
  }
  int old_left = 0;
  for (int i = 0; i < 200; ++i) {
    old_left += map.nearest(Eigen::Vector3f(0.05f + 0.1f * i, 0.05f, 0.05f), 1e-6f, idx, d2);
  }
  EXPECT_LE(old_left, 56);
}

/// A static wall (re-observed by every keyframe) and a "person": a 0.4 m block that moves
/// 0.5 m between keyframes, as a walker between two keyframes.
GaussianCloud wall_and_person(unsigned seed, float person_x, std::size_t& person_begin) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  GaussianCloud c;
  const auto add = [&c](const Eigen::Vector3f& p) {
    c.points_m.push_back(p);
    c.cov_m2.push_back(Eigen::Matrix3f::Identity() * 1e-3f);
    c.cov_raw_m2.push_back(Eigen::Matrix3f::Identity() * 1e-4f);
    c.colors_rgb.push_back({0, 0, 0});
  };
  for (int i = 0; i < 4000; ++i) add({-2.0f + 4.0f * u(rng), -1.0f + 2.0f * u(rng), 4.0f});
  person_begin = c.size();
  for (int i = 0; i < 400; ++i)
    add({person_x + 0.4f * u(rng), -0.5f + 1.0f * u(rng), 2.0f + 0.3f * u(rng)});
  return c;
}

TEST(LocalMap, OnlyReobservedPointsAreConfirmedAndMovingOnesArePruned) {
  LocalMap::Setting s;
  s.points_per_voxel = 64;
  s.confirm_distance_m = 0.05;
  s.confirm_keyframes = 2;
  LocalMap map(s);
  const geometry::Pose T = geometry::Pose::Identity();
  std::size_t person = 0;
  map.insert(wall_and_person(1, -1.0f, person), T);
  EXPECT_EQ(map.num_confirmed(), 0u);
  // Before any confirmation GICP may use every point (bootstrap).
  std::uint32_t j = 0;
  float d2 = 0.0f;
  EXPECT_TRUE(map.nearest(Eigen::Vector3f(-0.8f, 0.0f, 2.15f), 0.01f, j, d2));
  for (int k = 1; k <= 4; ++k) {
    map.insert(wall_and_person(1 + k, -1.0f + 0.5f * k, person), T);
  }
  // The wall is confirmed; the person's old positions never were and were pruned.
  EXPECT_GT(map.num_confirmed(), 3000u);
  EXPECT_GT(map.pruned_points(), 700u);
  // GICP's correspondences skip unconfirmed points: the person's current position (its
  // latest, tentative points) gives no match, the wall does.
  EXPECT_FALSE(map.nearest(Eigen::Vector3f(1.2f, 0.0f, 2.15f), 0.01f, j, d2));
  EXPECT_TRUE(map.nearest(Eigen::Vector3f(0.0f, 0.0f, 3.98f), 0.01f, j, d2));
  EXPECT_TRUE(map.confirmed(j));
  // Without confirmation every point is used at once.
  LocalMap::Setting off = s;
  off.confirm_distance_m = 0.0;
  LocalMap plain(off);
  plain.insert(wall_and_person(9, 0.2f, person), T);
  EXPECT_TRUE(plain.nearest(Eigen::Vector3f(0.4f, 0.0f, 2.15f), 0.01f, j, d2));
  // The skip mask keeps flagged points out.
  LocalMap masked(off);
  const GaussianCloud c = wall_and_person(9, 0.2f, person);
  std::vector<std::uint8_t> skip(c.size(), 0);
  for (std::size_t i = person; i < c.size(); ++i) skip[i] = 1;
  masked.insert(c, T, &skip);
  EXPECT_EQ(masked.num_points(), person);
  EXPECT_FALSE(masked.nearest(Eigen::Vector3f(0.4f, 0.0f, 2.15f), 0.01f, j, d2));
}

/// Four points in the voxel [0, 0.1)^3 of world, seen by a camera on the -z axis at `depth_m`
/// (camera frame = world shifted by depth_m along z), at in-voxel offset `offset_m`.
GaussianCloud voxel_points(float depth_m, float offset_m) {
  GaussianCloud c;
  for (int i = 0; i < 4; ++i) {
    c.points_m.emplace_back(0.02f + 0.02f * static_cast<float>(i), offset_m, offset_m + depth_m);
    c.cov_m2.push_back(Eigen::Matrix3f::Identity() * 1e-4f);
  }
  return c;
}

/// How many of `map`'s points lie at in-voxel offset `offset_m` (voxel_points' y).
int points_at_offset(const LocalMap& map, float offset_m) {
  int n = 0;
  map.for_each_point([&](const Eigen::Vector3f& p) { n += std::abs(p.y() - offset_m) < 1e-6f; });
  return n;
}

geometry::Pose camera_at_depth(float depth_m) {
  return geometry::make_pose(Eigen::Vector3d::Zero(),
                             Eigen::Vector3d(0.0, 0.0, -static_cast<double>(depth_m)));
}

TEST(LocalMap, AFullVoxelKeepsItsNearestSeenPoints) {
  LocalMap::Setting s;
  s.points_per_voxel = 4;
  s.radius_m = 100.0;
  s.replace_depth_ratio = 0.7;
  LocalMap map(s);
  map.insert(voxel_points(6.0f, 0.01f), camera_at_depth(6.0f));  // first seen from 6 m
  ASSERT_EQ(map.num_points(), 4u);
  // From 4.5 m (0.75 of 6 m, not clearly nearer): the 6 m points stay.
  map.insert(voxel_points(4.5f, 0.05f), camera_at_depth(4.5f));
  std::uint32_t j = 0;
  float d2 = 0.0f;
  ASSERT_TRUE(map.nearest(Eigen::Vector3f(0.04f, 0.05f, 0.05f), 1.0f, j, d2));
  EXPECT_NEAR(map.point(j).y(), 0.01f, 1e-6f);
  // From 1 m: the voxel now holds the near points only, and its count is unchanged.
  map.insert(voxel_points(1.0f, 0.09f), camera_at_depth(1.0f));
  EXPECT_EQ(map.num_points(), 4u);
  EXPECT_EQ(map.num_confirmed(), 4u);
  EXPECT_EQ(points_at_offset(map, 0.09f), 4);
  // With the ratio at 0 the first points stay whatever comes later.
  s.replace_depth_ratio = 0.0;
  LocalMap first(s);
  first.insert(voxel_points(6.0f, 0.01f), camera_at_depth(6.0f));
  first.insert(voxel_points(1.0f, 0.09f), camera_at_depth(1.0f));
  EXPECT_EQ(points_at_offset(first, 0.01f), 4);
}

TEST(LocalMap, HintedNearestIsExact) {
  // A hint (any point, near or far) only bounds the scan: the nearest point found is the same.
  LocalMap::Setting s;
  s.points_per_voxel = 64;
  LocalMap map(s);
  std::size_t person = 0;
  map.insert(wall_and_person(3, -1.0f, person), geometry::Pose::Identity());
  std::vector<Eigen::Vector3f> points;
  map.for_each_point([&](const Eigen::Vector3f& p) { points.push_back(p); });
  ASSERT_EQ(points.size(), map.num_points());
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> off(-0.06f, 0.06f);
  std::uint32_t found_with = 0, hints_tried = 0;
  for (int k = 0; k < 400; ++k) {
    const Eigen::Vector3f q = points[(static_cast<std::size_t>(k) * 37) % points.size()] +
                              Eigen::Vector3f(off(rng), off(rng), off(rng));
    std::uint32_t j0 = 0, j1 = 0, hint = 0;
    float d0 = 0.0f, d1 = 0.0f, dh = 0.0f;
    const bool f0 = map.nearest(q, 0.01f, j0, d0);
    // Hint: the nearest point of a query 5 cm away (a previous iteration's match), if any.
    if (!map.nearest(q + Eigen::Vector3f(0.05f, 0.0f, 0.0f), 0.04f, hint, dh)) {
      hint = LocalMap::kNoHint;
    } else {
      ++hints_tried;
    }
    const bool f1 = map.nearest(q, 0.01f, j1, d1, hint);
    ASSERT_EQ(f0, f1) << k;
    if (f0) {
      ++found_with;
      EXPECT_EQ(d0, d1) << k;
    }
  }
  EXPECT_GT(found_with, 200u);
  EXPECT_GT(hints_tried, 200u);
}

}  // namespace
}  // namespace vigs::tracking
