#include "rt/spsc_ring.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include "rt/counters.hpp"
#include "rt/queue_policy.hpp"
#include "tests/rt/rt_test_support.hpp"

namespace vigs::rt {
namespace {

// Counts constructions and destructions and detects double destruction / use after destroy.
struct Tracked {
  static inline int constructed = 0;
  static inline int destroyed = 0;
  static inline int errors = 0;
  static constexpr std::uint32_t kAlive = 0xA11FEu;
  static constexpr std::uint32_t kDead = 0xDEADu;

  static void reset() { constructed = destroyed = errors = 0; }
  static int alive() { return constructed - destroyed; }

  explicit Tracked(int v = 0) : value(v) { ++constructed; }
  Tracked(const Tracked& o) : value(o.value) {
    check(o);
    ++constructed;
  }
  Tracked(Tracked&& o) noexcept : value(o.value) {
    check(o);
    ++constructed;
  }
  Tracked& operator=(const Tracked& o) {
    check(*this);
    check(o);
    value = o.value;
    return *this;
  }
  Tracked& operator=(Tracked&& o) noexcept {
    check(*this);
    check(o);
    value = o.value;
    return *this;
  }
  ~Tracked() {
    check(*this);
    magic = kDead;
    ++destroyed;
  }
  static void check(const Tracked& t) {
    if (t.magic != kAlive) ++errors;
  }

  int value;
  std::uint32_t magic = kAlive;
};

TEST(SpscRing, RejectsCapacityThatIsNotAPowerOfTwo) {
  EXPECT_THROW(SpscRing<int>(0), std::invalid_argument);
  EXPECT_THROW(SpscRing<int>(3), std::invalid_argument);
  EXPECT_THROW(SpscRing<int>(100), std::invalid_argument);
  EXPECT_NO_THROW(SpscRing<int>(1));
  EXPECT_NO_THROW(SpscRing<int>(1024));
}

TEST(SpscRing, IndicesSitOnSeparateCacheLines) {
  EXPECT_EQ(alignof(SpscRing<int>), kCacheLineSize);
  EXPECT_GE(sizeof(SpscRing<int>), 3 * kCacheLineSize);
  EXPECT_EQ(sizeof(SpscRing<int>) % kCacheLineSize, 0u);
}

TEST(SpscRing, FullAndEmpty) {
  SpscRing<int> ring(4);
  EXPECT_EQ(ring.capacity(), 4u);
  EXPECT_TRUE(ring.empty());
  EXPECT_EQ(ring.front(), nullptr);
  int out = -1;
  EXPECT_FALSE(ring.try_pop(out));
  EXPECT_EQ(out, -1);
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(ring.try_push(i));
  EXPECT_EQ(ring.size(), 4u);
  EXPECT_FALSE(ring.try_push(99));
  EXPECT_FALSE(ring.try_emplace(99));
  EXPECT_EQ(ring.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    ASSERT_NE(ring.front(), nullptr);
    EXPECT_EQ(*ring.front(), i);
    ring.pop();
  }
  EXPECT_TRUE(ring.empty());
  EXPECT_FALSE(ring.try_pop().has_value());
}

TEST(SpscRing, CapacityOne) {
  SpscRing<int> ring(1);
  EXPECT_TRUE(ring.try_push(7));
  EXPECT_FALSE(ring.try_push(8));
  EXPECT_EQ(ring.try_pop(), std::optional<int>(7));
  EXPECT_TRUE(ring.try_push(9));
  EXPECT_EQ(ring.try_pop(), std::optional<int>(9));
}

TEST(SpscRing, WrapsAroundManyTimes) {
  SpscRing<std::uint64_t> ring(8);
  std::uint64_t next_in = 0;
  std::uint64_t next_out = 0;
  for (int round = 0; round < 1000; ++round) {
    const int n = 1 + round % 8;
    for (int i = 0; i < n; ++i) ASSERT_TRUE(ring.try_push(next_in++));
    ASSERT_EQ(ring.size(), static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      std::uint64_t v = 0;
      ASSERT_TRUE(ring.try_pop(v));
      ASSERT_EQ(v, next_out++);
    }
  }
  EXPECT_TRUE(ring.empty());
}

TEST(SpscRing, ConstructsAndDestroysEveryElementExactlyOnce) {
  Tracked::reset();
  {
    SpscRing<Tracked> ring(8);
    for (int i = 0; i < 8; ++i) ASSERT_TRUE(ring.try_emplace(i));
    EXPECT_EQ(Tracked::alive(), 8);
    {
      Tracked t(100);
      EXPECT_FALSE(ring.try_push(t));             // full: nothing constructed
      EXPECT_FALSE(ring.try_push(std::move(t)));  // full: t not moved from
      EXPECT_EQ(t.value, 100);
    }
    EXPECT_EQ(Tracked::alive(), 8);
    Tracked out;
    for (int i = 0; i < 3; ++i) {
      ASSERT_TRUE(ring.try_pop(out));
      EXPECT_EQ(out.value, i);
    }
    EXPECT_EQ(Tracked::alive(), 5 + 1);  // five queued + `out`
    auto opt = ring.try_pop();
    ASSERT_TRUE(opt.has_value());
    EXPECT_EQ(opt->value, 3);
    // Wrap the indices so that the remaining elements straddle the end of the storage.
    for (int i = 0; i < 4; ++i) ASSERT_TRUE(ring.try_push(Tracked(10 + i)));
    EXPECT_EQ(ring.size(), 8u);
    // The ring is destroyed here with 8 live elements.
  }
  EXPECT_EQ(Tracked::alive(), 0);
  EXPECT_EQ(Tracked::errors, 0);
  EXPECT_GT(Tracked::constructed, 0);
}

TEST(SpscRing, MoveOnlyElements) {
  SpscRing<std::unique_ptr<int>> ring(2);
  auto a = std::make_unique<int>(1);
  ASSERT_TRUE(ring.try_push(std::move(a)));
  EXPECT_EQ(a, nullptr);
  ASSERT_TRUE(ring.try_emplace(std::make_unique<int>(2)));
  auto c = std::make_unique<int>(3);
  EXPECT_FALSE(ring.try_push(std::move(c)));
  ASSERT_NE(c, nullptr);  // a failed push leaves the argument intact
  EXPECT_EQ(*c, 3);

  std::unique_ptr<int> out;
  ASSERT_TRUE(ring.try_pop(out));
  EXPECT_EQ(*out, 1);
  auto opt = ring.try_pop();
  ASSERT_TRUE(opt.has_value());
  EXPECT_EQ(**opt, 2);
  EXPECT_TRUE(ring.empty());
}

TEST(SpscRing, PushOrDropCountsTheNewestDrops) {
  SpscRing<int> ring(4);
  Counter drops;
  int queued = 0;
  for (int i = 0; i < 10; ++i) queued += push_or_drop(ring, i, drops) ? 1 : 0;
  EXPECT_EQ(queued, 4);
  EXPECT_EQ(drops.get(), 6u);
  // The oldest were kept (drop newest).
  for (int i = 0; i < 4; ++i) EXPECT_EQ(ring.try_pop(), std::optional<int>(i));
}

TEST(SpscRing, PushOrDropHandsTheRejectedItemBack) {
  SpscRing<std::unique_ptr<int>> ring(1);
  SingleWriterCounter drops;
  std::vector<int> returned;
  auto on_drop = [&](std::unique_ptr<int>& p) { returned.push_back(*p); };
  auto a = std::make_unique<int>(1);
  auto b = std::make_unique<int>(2);
  EXPECT_TRUE(push_or_drop(ring, a, drops, on_drop));
  EXPECT_FALSE(push_or_drop(ring, b, drops, on_drop));
  EXPECT_EQ(drops.get(), 1u);
  EXPECT_EQ(returned, std::vector<int>{2});
}

TEST(SpscRing, TrimOldestKeepsTheNewest) {
  SpscRing<int> ring(8);
  Counter drops;
  for (int i = 0; i < 7; ++i) ASSERT_TRUE(ring.try_push(i));
  std::vector<int> merged;
  EXPECT_EQ(trim_oldest(ring, 3, drops, [&](int& v) { merged.push_back(v); }), 4u);
  EXPECT_EQ(drops.get(), 4u);
  EXPECT_EQ(merged, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(ring.size(), 3u);
  EXPECT_EQ(ring.try_pop(), std::optional<int>(4));
  EXPECT_EQ(trim_oldest(ring, 3, drops), 0u);
  EXPECT_EQ(drops.get(), 4u);
}

// Two threads, every value once and in order; the sum checks nothing was duplicated or lost.
TEST(SpscRing, TwoThreadsTransferEveryItemInOrder) {
  const std::uint64_t n = test::stress_items(10'000'000);
  SpscRing<std::uint64_t> ring(1024);
  std::uint64_t sum = 0;
  std::uint64_t order_errors = 0;
  std::thread consumer([&] {
    std::uint64_t expected = 0;
    test::Backoff backoff;
    while (expected < n) {
      // Alternate the two consumer APIs.
      if ((expected & 1) == 0) {
        std::uint64_t v = 0;
        if (!ring.try_pop(v)) {
          backoff.pause();
          continue;
        }
        order_errors += v != expected ? 1 : 0;
        sum += v;
      } else {
        const std::uint64_t* p = ring.front();
        if (p == nullptr) {
          backoff.pause();
          continue;
        }
        order_errors += *p != expected ? 1 : 0;
        sum += *p;
        ring.pop();
      }
      ++expected;
    }
  });
  test::Backoff backoff;
  for (std::uint64_t i = 0; i < n; ++i) {
    while (!ring.try_push(i)) backoff.pause();
  }
  consumer.join();
  EXPECT_EQ(order_errors, 0u);
  EXPECT_EQ(sum, n * (n - 1) / 2);
  EXPECT_TRUE(ring.empty());
}

// Elements with owned memory crossing threads: nothing leaks, nothing is freed twice (ASan/TSan
// builds check the memory side).
TEST(SpscRing, TwoThreadsMoveOwningElements) {
  const std::uint64_t n = test::stress_items(200'000);
  SpscRing<std::unique_ptr<std::uint64_t>> ring(64);
  std::uint64_t sum = 0;
  std::thread consumer([&] {
    test::Backoff backoff;
    for (std::uint64_t got = 0; got < n;) {
      if (auto p = ring.try_pop()) {
        sum += **p;
        ++got;
      } else {
        backoff.pause();
      }
    }
  });
  test::Backoff backoff;
  for (std::uint64_t i = 0; i < n; ++i) {
    auto item = std::make_unique<std::uint64_t>(i);
    while (!ring.try_push(std::move(item))) backoff.pause();
  }
  consumer.join();
  EXPECT_EQ(sum, n * (n - 1) / 2);
}

}  // namespace
}  // namespace vigs::rt
