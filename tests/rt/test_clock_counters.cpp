#include <gtest/gtest.h>

#include <cstdint>
#include <thread>

#include "rt/clock.hpp"
#include "rt/counters.hpp"

namespace vigs::rt {
namespace {

TEST(Clock, MonotonicNeverGoesBack) {
  std::int64_t last = monotonic_ns();
  EXPECT_GT(last, 0);
  for (int i = 0; i < 10000; ++i) {
    const std::int64_t now = monotonic_ns();
    ASSERT_GE(now, last);
    last = now;
  }
}

TEST(Clock, Conversions) {
  static_assert(ms_to_ns(50) == 50'000'000);
  static_assert(us_to_ns(3) == 3'000);
  static_assert(s_to_ns(std::int64_t{2}) == 2'000'000'000);
  static_assert(s_to_ns(0.05) == 50'000'000);
  static_assert(s_to_ns(-0.5) == -500'000'000);
  EXPECT_DOUBLE_EQ(ns_to_ms(1'500'000), 1.5);
  EXPECT_DOUBLE_EQ(ns_to_us(2'500), 2.5);
  EXPECT_DOUBLE_EQ(ns_to_s(250'000'000), 0.25);

  constexpr timespec ts = to_timespec(1'500'000'123);
  static_assert(ts.tv_sec == 1 && ts.tv_nsec == 500'000'123);
  constexpr timespec neg = to_timespec(-1);
  static_assert(neg.tv_sec == -1 && neg.tv_nsec == 999'999'999);
  static_assert(from_timespec(to_timespec(-1'234'567'890)) == -1'234'567'890);
}

TEST(Clock, SleepUntilAnAbsoluteDeadline) {
  const std::int64_t start = monotonic_ns();
  sleep_until_ns(start + ms_to_ns(2));
  EXPECT_GE(monotonic_ns(), start + ms_to_ns(2));
  // A deadline in the past returns at once.
  const std::int64_t before = monotonic_ns();
  sleep_until_ns(before - ms_to_ns(100));
  EXPECT_LT(monotonic_ns() - before, ms_to_ns(100));
}

TEST(Counters, CounterIsExactAcrossThreads) {
  Counter c;
  constexpr int kPerThread = 100000;
  std::thread t([&] {
    for (int i = 0; i < kPerThread; ++i) c.add();
  });
  for (int i = 0; i < kPerThread; ++i) c.add(2);
  t.join();
  EXPECT_EQ(c.get(), 3u * kPerThread);
  c.reset();
  EXPECT_EQ(c.get(), 0u);
}

TEST(Counters, SingleWriterCounterReadFromAnotherThread) {
  SingleWriterCounter c;
  std::uint64_t seen = 0;
  std::thread reader([&] {
    while (seen < 5000) {
      const std::uint64_t v = c.get();
      ASSERT_GE(v, seen);
      seen = v;
    }
  });
  for (int i = 0; i < 5000; ++i) c.add();
  reader.join();
  EXPECT_EQ(c.get(), 5000u);
}

TEST(Counters, HighWaterMarkAndPadding) {
  HighWaterMark hw;
  for (std::uint64_t v : {3u, 9u, 4u, 7u}) hw.observe(v);
  EXPECT_EQ(hw.get(), 9u);
  static_assert(alignof(PaddedCounter) == kCacheLineSize);
  PaddedCounter counters[2];
  EXPECT_GE(reinterpret_cast<char*>(&counters[1]) - reinterpret_cast<char*>(&counters[0]),
            static_cast<std::ptrdiff_t>(kCacheLineSize));
  counters[1].add(4);
  EXPECT_EQ(counters[1].get(), 4u);
}

}  // namespace
}  // namespace vigs::rt
