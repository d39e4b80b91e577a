// The insertion's voxel occupancy (mapping/voxel_occupancy.hpp): the same membership as a set
// of voxel keys, in a fraction of its bytes for a mapped surface.
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <tuple>

#include <gtest/gtest.h>

#include "mapping/voxel_occupancy.hpp"

namespace vigs::mapping {
namespace {

using Key = std::tuple<std::int64_t, std::int64_t, std::int64_t>;

Key voxel_key(double x, double y, double z, double voxel_m) {
  return {static_cast<std::int64_t>(std::floor(x / voxel_m)),
          static_cast<std::int64_t>(std::floor(y / voxel_m)),
          static_cast<std::int64_t>(std::floor(z / voxel_m))};
}

TEST(MappingVoxelOccupancy, HoldsExactlyTheVoxelsASetOfKeysHolds) {
  constexpr double kVoxel = 0.02;
  VoxelOccupancy occ(kVoxel);
  std::set<Key> ref;
  std::mt19937 rng(7);
  // both signs, and points on voxel and brick faces (multiples of the voxel size)
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  std::uniform_int_distribution<int> face(-20, 20);
  std::uniform_int_distribution<int> what(0, 3);
  for (int step = 0; step < 20000; ++step) {
    double x = u(rng), y = u(rng), z = u(rng);
    if (step % 5 == 0) x = face(rng) * kVoxel;
    if (step % 7 == 0) y = face(rng) * kVoxel;
    const Key k = voxel_key(x, y, z, kVoxel);
    switch (what(rng)) {
      case 0:
      case 1:
        ASSERT_EQ(occ.insert(x, y, z), ref.insert(k).second) << step;
        break;
      case 2:
        occ.erase(x, y, z);
        ref.erase(k);
        break;
      default:
        ASSERT_EQ(occ.contains(x, y, z), ref.count(k) == 1) << step;
    }
    ASSERT_EQ(occ.voxels(), ref.size()) << step;
  }
  ASSERT_GT(ref.size(), 1000u);
  // every voxel of the region: members and non-members agree
  for (int i = -16; i < 16; ++i)
    for (int j = -16; j < 16; ++j)
      for (int k = -16; k < 16; ++k) {
        const double x = (i + 0.5) * kVoxel, y = (j + 0.5) * kVoxel, z = (k + 0.5) * kVoxel;
        ASSERT_EQ(occ.contains(x, y, z), ref.count(voxel_key(x, y, z, kVoxel)) == 1);
      }
  // erasing what is left empties every brick
  for (const auto& [i, j, k] : ref)
    occ.erase((i + 0.5) * kVoxel, (j + 0.5) * kVoxel, (k + 0.5) * kVoxel);
  EXPECT_EQ(occ.voxels(), 0u);
  EXPECT_EQ(occ.bricks(), 0u);
  occ.clear();
  EXPECT_EQ(occ.bytes(), 0u);
}

// A wall seen square-on and a slanted floor, sampled a voxel apart: a mapped surface. A set of
// 8-byte keys needs at least 9 bytes per voxel (key and control byte at a full table), 10-20 at
// Abseil's load factors; the bricks need a few.
TEST(MappingVoxelOccupancy, ASurfaceCostsAFewBytesPerVoxel) {
  constexpr double kVoxel = 0.02;
  VoxelOccupancy occ(kVoxel);
  for (int i = 0; i < 150; ++i)
    for (int j = 0; j < 150; ++j) {
      occ.insert(1.0 + 0.013, (i + 0.5) * kVoxel, (j + 0.5) * kVoxel);               // wall x = 1
      occ.insert((i + 0.5) * kVoxel, (j + 0.5) * kVoxel, 0.3 * (i + 0.5) * kVoxel);  // floor
    }
  ASSERT_GT(occ.voxels(), 40000u);
  const double per_voxel = static_cast<double>(occ.bytes()) / static_cast<double>(occ.voxels());
  EXPECT_LT(per_voxel, 6.0) << occ.bricks() << " bricks";
  EXPECT_GT(per_voxel, 0.0);
}

}  // namespace
}  // namespace vigs::mapping
