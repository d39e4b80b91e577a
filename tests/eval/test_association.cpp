#include <gtest/gtest.h>

#include "eval/association.hpp"

namespace vigs::eval {
namespace {

TEST(Association, GreedyTakesSmallestDifferenceFirstAndUsesEachStampOnce) {
  // b=1.005 is closest to a=1.00 (0.005) and to a=1.01 (0.005): tie broken by earlier t_a.
  const std::vector<double> a = {1.00, 1.01, 2.00};
  const std::vector<double> b = {1.005, 1.013, 5.0};
  const auto m = associate(a, b, 0.02);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].a, 0u);
  EXPECT_EQ(m[0].b, 0u);
  EXPECT_EQ(m[1].a, 1u);  // 1.01 takes 1.013 (0.003 < 0.005), decided first
  EXPECT_EQ(m[1].b, 1u);
}

TEST(Association, GreedyIsNotNearestNeighbour) {
  // a0=0.0 has nearest b0=0.009, but a1=0.010 claims b0 first (0.001); a0 gets nothing
  // within 0.01 and stays unmatched.
  const std::vector<double> a = {0.0, 0.010};
  const std::vector<double> b = {0.009, 0.025};
  const auto m = associate(a, b, 0.01);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].a, 1u);
  EXPECT_EQ(m[0].b, 0u);
}

TEST(Association, StrictWindowOffsetAndUnsortedInput) {
  const std::vector<double> a = {3.0, 1.0, 2.0};
  const std::vector<double> b = {2.02, 0.5, 1.02};
  EXPECT_EQ(associate(a, b, 0.02).size(), 0u);  // |dt| == 0.02 is not < 0.02 (up to rounding)
  const auto m = associate(a, b, 0.0201);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].a, 1u);  // sorted by t_a
  EXPECT_EQ(m[0].b, 2u);
  EXPECT_EQ(m[1].a, 2u);
  EXPECT_EQ(m[1].b, 0u);
  const auto shifted = associate(a, b, 0.001, -0.02);  // b + offset
  EXPECT_EQ(shifted.size(), 2u);
}

TEST(Association, EmptyInputs) {
  EXPECT_TRUE(associate({}, {1.0}, 0.1).empty());
  EXPECT_TRUE(associate({1.0}, {}, 0.1).empty());
}

}  // namespace
}  // namespace vigs::eval
