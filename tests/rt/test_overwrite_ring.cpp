#include "rt/overwrite_ring.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <thread>

#include "tests/rt/rt_test_support.hpp"

namespace vigs::rt {
namespace {

// Larger than one word, with redundancy so that a torn copy is detectable.
struct Stamped {
  std::uint64_t value = 0;
  std::uint64_t inverted = ~std::uint64_t{0};
  double value_as_double = 0.0;
  std::uint32_t low = 0;
};

Stamped make(std::uint64_t v) {
  return Stamped{v, ~v, static_cast<double>(v), static_cast<std::uint32_t>(v)};
}
bool intact(const Stamped& s) {
  return s.inverted == ~s.value && s.value_as_double == static_cast<double>(s.value) &&
         s.low == static_cast<std::uint32_t>(s.value);
}

TEST(OverwriteRing, RejectsCapacityThatIsNotAPowerOfTwo) {
  EXPECT_THROW(OverwriteRing<int>(0), std::invalid_argument);
  EXPECT_THROW(OverwriteRing<int>(6), std::invalid_argument);
}

TEST(OverwriteRing, OverwritesTheOldestAndCountsIt) {
  OverwriteRing<int> ring(4);
  for (int i = 1; i <= 4; ++i) EXPECT_TRUE(ring.push(i));
  for (int i = 5; i <= 10; ++i) EXPECT_FALSE(ring.push(i));  // each overwrites one unread value
  EXPECT_EQ(ring.overwritten(), 6u);
  EXPECT_EQ(ring.size(), 4u);
  for (int i = 7; i <= 10; ++i) {
    int v = 0;
    ASSERT_TRUE(ring.try_pop(v));
    EXPECT_EQ(v, i);
  }
  int v = 0;
  EXPECT_FALSE(ring.try_pop(v));
  EXPECT_TRUE(ring.empty());
}

TEST(OverwriteRing, CapacityOneIsALatestValueMailbox) {
  OverwriteRing<Stamped> box(1);
  Stamped s;
  EXPECT_FALSE(box.try_pop(s));
  box.push(make(1));
  box.push(make(2));
  box.push(make(3));
  ASSERT_TRUE(box.try_pop(s));
  EXPECT_EQ(s.value, 3u);
  EXPECT_TRUE(intact(s));
  EXPECT_EQ(box.overwritten(), 2u);
  EXPECT_FALSE(box.try_pop(s));
}

TEST(OverwriteRing, PopLatestSkipsToTheNewest) {
  OverwriteRing<int> ring(8);
  for (int i = 0; i < 5; ++i) ring.push(i);
  int v = -1;
  ASSERT_TRUE(ring.try_pop_latest(v));
  EXPECT_EQ(v, 4);
  EXPECT_EQ(ring.overwritten(), 0u);
  EXPECT_FALSE(ring.try_pop_latest(v));
}

// The producer runs flat out into a small ring while the consumer drains it: values arrive in
// increasing order, intact, and delivered + overwritten == produced.
TEST(OverwriteRing, ConcurrentProducerAndConsumer) {
  const std::uint64_t n = test::stress_items(2'000'000);
  OverwriteRing<Stamped> ring(8);
  std::atomic<bool> done{false};
  std::uint64_t delivered = 0;
  std::uint64_t order_errors = 0;
  std::uint64_t torn = 0;
  std::thread consumer([&] {
    std::uint64_t last = 0;  // values start at 1
    Stamped s;
    test::Backoff backoff;
    for (;;) {
      const bool finished = done.load(std::memory_order_acquire);
      bool got_any = false;
      while (ring.try_pop(s)) {
        got_any = true;
        ++delivered;
        torn += intact(s) ? 0 : 1;
        order_errors += s.value > last ? 0 : 1;
        last = s.value;
      }
      if (finished && !got_any) break;
      if (!got_any) backoff.pause();
    }
  });
  for (std::uint64_t i = 1; i <= n; ++i) ring.push(make(i));
  done.store(true, std::memory_order_release);
  consumer.join();

  EXPECT_EQ(torn, 0u);
  EXPECT_EQ(order_errors, 0u);
  EXPECT_EQ(delivered + ring.overwritten(), n);
  EXPECT_GT(delivered, 0u);
  EXPECT_TRUE(ring.empty());
}

}  // namespace
}  // namespace vigs::rt
