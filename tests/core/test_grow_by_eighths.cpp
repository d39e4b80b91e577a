// Growth by eighths (core/grow_by_eighths.hpp): a map grown a few Gaussians at a time keeps its
// unused capacity under an eighth, where std::vector's doubling leaves up to half unused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>

#include "core/grow_by_eighths.hpp"
#include "mapping/gaussian_map.hpp"

namespace vigs {
namespace {

TEST(GrowByEighths, SlackStaysUnderAnEighthWhileAVectorGrows) {
  std::vector<std::uint32_t> v;
  std::size_t reallocations = 0;
  for (std::size_t n = 1; n <= 200000; n += 37) {
    const std::size_t before = v.capacity();
    resize_by_eighths(v, n);
    if (v.capacity() != before) ++reallocations;
    ASSERT_EQ(v.size(), n);
    ASSERT_LE(v.capacity(), n + n / 8 + 37) << "at size " << n;
  }
  // logarithmic: 1.125^k from 37 to 200000 is about 73 steps
  EXPECT_LT(reallocations, 120u);
}

TEST(GrowByEighths, AMapGrownAKeyframeAtATimeHoldsLittleUnusedCapacity) {
  mapping::GaussianMap map;
  const float mean[3] = {0, 0, 1}, ls[3] = {-3, -3, -3}, q[4] = {1, 0, 0, 0}, rgb[3] = {1, 1, 1};
  double worst = 0.0;
  for (int keyframe = 0; keyframe < 300; ++keyframe) {
    for (int i = 0; i < 500; ++i) map.push_back(mean, ls, q, 0.0f, rgb);
    const double used = static_cast<double>(map.size() * 14 * sizeof(float));
    worst = std::max(worst, static_cast<double>(map.capacity_bytes()) / used);
  }
  std::printf("largest capacity / size over 300 keyframes: %.3f\n", worst);
  EXPECT_LT(worst, 1.13);  // doubling reaches 2
}

}  // namespace
}  // namespace vigs
