// PlaybackPacer: the real-time schedule of a played clip, on a scripted clock.
#include "drivers/common/playback_pacer.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace vigs::drivers {
namespace {

constexpr std::int64_t kMs = 1'000'000;

TEST(PlaybackPacer, FirstFrameAnchorsAndLaterFramesAreDueAtTheirRecordedSpacing) {
  PlaybackPacer p(1.0, 1000 * kMs);
  EXPECT_EQ(p.due_ns(5'000 * kMs, 100 * kMs), 100 * kMs);  // anchor: due at once
  // Read early (as OpenNI2's manual player hands the next record at once): held to its time.
  EXPECT_EQ(p.due_ns(5'050 * kMs, 101 * kMs), 150 * kMs);
  EXPECT_EQ(p.due_ns(5'100 * kMs, 151 * kMs), 200 * kMs);
  // Read late: still due at its time (in the past), so the caller does not wait; the schedule
  // does not move, so a late frame does not delay the next ones.
  EXPECT_EQ(p.due_ns(5'150 * kMs, 290 * kMs), 250 * kMs);
  EXPECT_EQ(p.due_ns(5'200 * kMs, 291 * kMs), 300 * kMs);
  // Minutes later there is no drift: the schedule is absolute, not frame to frame.
  EXPECT_EQ(p.due_ns(5'000 * kMs + 180'000 * kMs, 180'000 * kMs), 180'100 * kMs);
  EXPECT_EQ(p.reanchors(), 0u);
}

TEST(PlaybackPacer, SpeedScalesTheSchedule) {
  PlaybackPacer twice(2.0, 1000 * kMs);
  (void)twice.due_ns(0, 0);
  EXPECT_EQ(twice.due_ns(100 * kMs, 0), 50 * kMs);
  PlaybackPacer half(0.5, 1000 * kMs);
  (void)half.due_ns(0, 0);
  EXPECT_EQ(half.due_ns(100 * kMs, 0), 200 * kMs);
}

TEST(PlaybackPacer, ClipStartingOverOrALongGapReanchorsAndIsCounted) {
  PlaybackPacer p(1.0, 1000 * kMs);
  (void)p.due_ns(1'000 * kMs, 0);
  EXPECT_EQ(p.due_ns(1'050 * kMs, 10 * kMs), 50 * kMs);
  // Device time goes back: the clip started over; due at once, new anchor.
  EXPECT_EQ(p.due_ns(0, 60 * kMs), 60 * kMs);
  EXPECT_EQ(p.reanchors(), 1u);
  EXPECT_EQ(p.due_ns(50 * kMs, 61 * kMs), 110 * kMs);
  // A 5 s gap in the recording would be held 5 s: longer than max_hold, so it re-anchors.
  EXPECT_EQ(p.due_ns(5'100 * kMs, 112 * kMs), 112 * kMs);
  EXPECT_EQ(p.reanchors(), 2u);
  EXPECT_EQ(p.due_ns(5'150 * kMs, 113 * kMs), 162 * kMs);
  // reset() (a reopened device) forgets the anchor without counting.
  p.reset();
  EXPECT_EQ(p.due_ns(9'000 * kMs, 500 * kMs), 500 * kMs);
  EXPECT_EQ(p.reanchors(), 2u);
}

}  // namespace
}  // namespace vigs::drivers
