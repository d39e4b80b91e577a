// HistoryRing: first in, first out, the oldest dropped when full, across the wrap-around.
#include "core/history_ring.hpp"

#include <gtest/gtest.h>

namespace vigs {
namespace {

TEST(HistoryRing, KeepsTheNewestInOrderAndDropsTheOldestWhenFull) {
  HistoryRing<int> r(3);
  EXPECT_TRUE(r.empty());
  EXPECT_EQ(r.capacity(), 3u);
  EXPECT_FALSE(r.push_back(1));
  EXPECT_FALSE(r.push_back(2));
  EXPECT_FALSE(r.push_back(3));
  EXPECT_TRUE(r.full());
  EXPECT_TRUE(r.push_back(4));  // 1 falls off
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0], 2);
  EXPECT_EQ(r[1], 3);
  EXPECT_EQ(r[2], 4);
  EXPECT_EQ(r.front(), 2);
}

TEST(HistoryRing, PopsFromTheFrontAcrossTheWrapAround) {
  HistoryRing<int> r(4);
  // Push one, keep two: the indices go round the storage 25 times.
  for (int i = 0; i < 100; ++i) {
    EXPECT_FALSE(r.push_back(i));
    if (r.size() > 2) r.pop_front();
    ASSERT_EQ(r.size(), i == 0 ? 1u : 2u);
    EXPECT_EQ(r[r.size() - 1], i);
    EXPECT_EQ(r.front(), i == 0 ? 0 : i - 1);
  }
}

TEST(HistoryRing, CapacityIsAtLeastOne) {
  HistoryRing<int> r(0);
  EXPECT_EQ(r.capacity(), 1u);
  EXPECT_FALSE(r.push_back(7));
  EXPECT_TRUE(r.push_back(8));
  EXPECT_EQ(r.front(), 8);
}

}  // namespace
}  // namespace vigs
