// The OpenNI2 driver's pairing and stamping rules, without OpenNI2: FramePairer decides which
// depth and colour frames form an RGB-D frame, DeviceClock maps device microseconds to host
// CLOCK_MONOTONIC nanoseconds.
#include <gtest/gtest.h>

#include "drivers/common/frame_pairer.hpp"
#include "drivers/openni2/device_clock.hpp"

namespace vigs::drivers {
namespace {

TEST(FramePairer, EqualStampsPairInEitherOrder) {
  FramePairer p(16'667);
  EXPECT_FALSE(p.add_depth(1000));
  EXPECT_EQ(p.step(), PairStep::kWait);
  EXPECT_FALSE(p.add_colour(1000));
  EXPECT_EQ(p.step(), PairStep::kPair);
  EXPECT_FALSE(p.depth_pending());
  EXPECT_FALSE(p.colour_pending());
  EXPECT_FALSE(p.add_colour(34'333));
  EXPECT_EQ(p.step(), PairStep::kWait);
  EXPECT_FALSE(p.add_depth(34'333));
  EXPECT_EQ(p.step(), PairStep::kPair);
}

TEST(FramePairer, NearestWithinToleranceElseOlderIsUnpaired) {
  FramePairer p(16'667);
  ASSERT_FALSE(p.add_depth(100'000));
  ASSERT_FALSE(p.add_colour(116'667));  // exactly at the tolerance: pairs
  EXPECT_EQ(p.step(), PairStep::kPair);

  // Colour lost one frame: depth 133 ms waits, colour 166 ms arrives, depth is the older one.
  ASSERT_FALSE(p.add_depth(133'333));
  EXPECT_EQ(p.step(), PairStep::kWait);
  ASSERT_FALSE(p.add_colour(166'667));
  EXPECT_EQ(p.step(), PairStep::kDiscardDepth);
  EXPECT_TRUE(p.colour_pending());
  EXPECT_EQ(p.step(), PairStep::kWait);
  ASSERT_FALSE(p.add_depth(166'000));
  EXPECT_EQ(p.step(), PairStep::kPair);

  // Depth lost one frame: the older colour goes.
  ASSERT_FALSE(p.add_colour(200'000));
  ASSERT_FALSE(p.add_depth(233'333));
  EXPECT_EQ(p.step(), PairStep::kDiscardColour);
  EXPECT_TRUE(p.depth_pending());
  EXPECT_FALSE(p.colour_pending());
}

TEST(FramePairer, ASecondFrameOfOneStreamDisplacesTheFirst) {
  FramePairer p(10);
  EXPECT_FALSE(p.add_depth(0));
  EXPECT_TRUE(p.add_depth(33));  // the first depth frame is unpaired
  EXPECT_FALSE(p.add_colour(30));
  EXPECT_EQ(p.step(), PairStep::kPair);
  p.add_colour(50);
  p.reset();
  EXPECT_FALSE(p.colour_pending());
  EXPECT_EQ(p.step(), PairStep::kWait);
}

TEST(DeviceClock, KeepsDeviceSpacingFromTheFirstFrame) {
  DeviceClock c;
  EXPECT_EQ(c.to_host_ns(1000, 5'000'000'000), 5'000'000'000);
  // Read late or early: the stamp follows the device clock, not the read time.
  EXPECT_EQ(c.to_host_ns(34'333, 5'090'000'000), 5'033'333'000);
  EXPECT_EQ(c.to_host_ns(67'667, 5'040'000'000), 5'066'667'000);
  EXPECT_EQ(c.reanchors(), 0u);
}

TEST(DeviceClock, ReanchorsWhenDeviceTimeGoesBackAndStaysIncreasing) {
  DeviceClock c;
  const std::int64_t a = c.to_host_ns(1'000'000, 10'000'000'000);
  const std::int64_t b = c.to_host_ns(2'000'000, 11'000'000'000);
  EXPECT_EQ(b - a, 1'000'000'000);
  // Device restarted: re-anchored on this read, but never before the previous stamp.
  const std::int64_t r = c.to_host_ns(500, 10'500'000'000);
  EXPECT_EQ(c.reanchors(), 1u);
  EXPECT_EQ(r, b + 1);
  const std::int64_t s = c.to_host_ns(1500, 10'600'000'000);
  EXPECT_GT(s, r);
  EXPECT_EQ(c.to_host_ns(1500, 0), s + 1);  // repeated device time: still strictly increasing
}

}  // namespace
}  // namespace vigs::drivers
