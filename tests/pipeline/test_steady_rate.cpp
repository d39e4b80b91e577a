// The steady-state real-time factor (pipeline/steady_rate.hpp): start-up and drain do not enter
// it; a pipeline that falls behind shows its own rate.
#include <gtest/gtest.h>

#include <cstdio>

#include "pipeline/steady_rate.hpp"

namespace vigs::pipeline {
namespace {

constexpr std::int64_t kPeriodNs = 50'000'000;  // 20 Hz camera

TEST(SteadyRealTimeFactor, StartUpAndDrainDoNotCount) {
  // 1000 frames; the first 20 poses come 3 s late (start-up), the last 20 are drained 2 s after
  // the stream ended; in between one pose per camera period.
  std::vector<std::int64_t> stream, done;
  for (int i = 0; i < 1000; ++i) {
    stream.push_back(i * kPeriodNs);
    std::int64_t t = 3'000'000'000 + i * kPeriodNs + 10'000'000;
    if (i >= 980) t += 2'000'000'000;
    done.push_back(t);
  }
  const double whole = static_cast<double>(stream.back() - stream.front()) /
                       static_cast<double>(done.back() - stream.front());
  const std::optional<double> steady = steady_real_time_factor(stream, done);
  ASSERT_TRUE(steady);
  std::printf("whole run %.3f, steady %.3f\n", whole, *steady);
  EXPECT_LT(whole, 0.95);  // 50 s of stream over 55 s of wall time
  EXPECT_NEAR(*steady, 1.0, 1e-12);
}

TEST(SteadyRealTimeFactor, APipelineThatFallsBehindShowsItsOwnRate) {
  std::vector<std::int64_t> stream, done;
  for (int i = 0; i < 500; ++i) {
    stream.push_back(i * kPeriodNs);
    done.push_back(std::int64_t{i} * 60'000'000);  // a pose every 60 ms against frames every 50 ms
  }
  const std::optional<double> steady = steady_real_time_factor(stream, done);
  ASSERT_TRUE(steady);
  EXPECT_NEAR(*steady, 50.0 / 60.0, 1e-12);
}

TEST(EventsInSteadyWindow, CountsOnlyBetweenTheSteadyFrames) {
  // 100 poses 50 ms apart: the window runs from pose 9 (trim 0.1 of 99 intervals) to pose 90.
  std::vector<std::int64_t> done;
  for (int i = 0; i < 100; ++i) done.push_back(i * kPeriodNs);
  const std::vector<std::int64_t> events{
      2 * kPeriodNs,        // start-up: out
      9 * kPeriodNs,        // at the window's first pose: out (after it only)
      9 * kPeriodNs + 1,    // in
      50 * kPeriodNs,       // in
      90 * kPeriodNs,       // at the last pose: in
      90 * kPeriodNs + 1,   // drain: out
      99 * kPeriodNs + 7};  // out
  EXPECT_EQ(events_in_steady_window(done, events), 3u);
  EXPECT_EQ(events_in_steady_window(done, {}), 0u);
  EXPECT_FALSE(events_in_steady_window({0, kPeriodNs}, events));
}

TEST(SteadyRealTimeFactor, NothingWithoutEnoughFramesOrWallTime) {
  EXPECT_FALSE(steady_real_time_factor({0, kPeriodNs}, {0, kPeriodNs}));
  EXPECT_FALSE(steady_real_time_factor({0, 1, 2}, {0, 1}));
  EXPECT_FALSE(steady_real_time_factor({0, 1, 2}, {5, 5, 5}));
  EXPECT_FALSE(steady_real_time_factor({0, 1, 2}, {0, 1, 2}, 0.5));
  EXPECT_TRUE(steady_real_time_factor({0, 1, 2}, {0, 1, 2}));
}

}  // namespace
}  // namespace vigs::pipeline
