#include "rt/frame_pool.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "rt/counters.hpp"
#include "rt/queue_policy.hpp"
#include "rt/spsc_ring.hpp"
#include "tests/rt/rt_test_support.hpp"

namespace vigs::rt {
namespace {

FramePoolSettings small_settings(std::uint32_t slots) {
  FramePoolSettings s;
  s.slots = slots;
  s.width = 32;
  s.height = 24;
  s.colour_channels = 3;
  return s;
}

TEST(FramePool, RejectsEmptySettings) {
  EXPECT_THROW(FramePool(small_settings(0)), std::invalid_argument);
  FramePoolSettings s = small_settings(2);
  s.width = 0;
  EXPECT_THROW(FramePool{s}, std::invalid_argument);
}

TEST(FramePool, AcquireAllThenExhaustionIsCounted) {
  FramePool pool(small_settings(4));
  EXPECT_EQ(pool.capacity(), 4u);
  EXPECT_EQ(pool.available(), 4u);
  std::vector<FrameHandle> held;
  std::set<std::uint32_t> indices;
  std::set<const void*> buffers;
  for (int i = 0; i < 4; ++i) {
    const FrameHandle h = pool.acquire();
    ASSERT_TRUE(h.valid());
    held.push_back(h);
    indices.insert(h.index);
    Frame& f = pool.frame(h);
    EXPECT_EQ(f.colour.size(), 32u * 24u * 3u);
    EXPECT_EQ(f.depth.size(), 32u * 24u);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(f.colour.data()) % kCacheLineSize, 0u);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(f.depth.data()) % kCacheLineSize, 0u);
    buffers.insert(f.colour.data());
    buffers.insert(f.depth.data());
  }
  EXPECT_EQ(indices.size(), 4u);
  EXPECT_EQ(buffers.size(), 8u);
  EXPECT_EQ(pool.available(), 0u);
  EXPECT_EQ(pool.exhausted(), 0u);

  EXPECT_FALSE(pool.acquire().valid());
  EXPECT_FALSE(pool.acquire().valid());
  EXPECT_EQ(pool.exhausted(), 2u);

  pool.release(held[2]);
  EXPECT_EQ(pool.available(), 1u);
  const FrameHandle again = pool.acquire();
  EXPECT_EQ(again, held[2]);
  held[2] = again;
  for (FrameHandle h : held) pool.release(h);
  EXPECT_EQ(pool.available(), 4u);
  pool.release(FrameHandle{});  // invalid handles are ignored
  EXPECT_EQ(pool.available(), 4u);
}

TEST(FramePool, SlotIsFreeOnlyAfterTheLastReference) {
  FramePool pool(small_settings(2));
  const FrameHandle h = pool.acquire();
  pool.retain(h);  // e.g. a second consumer (recorder)
  EXPECT_EQ(pool.available(), 1u);
  pool.release(h);
  EXPECT_EQ(pool.available(), 1u);
  pool.release(h);
  EXPECT_EQ(pool.available(), 2u);
}

// Driver thread fills frames and pushes handles; tracker thread checks and releases them.
// Full ring: the newest handle is dropped, counted and returned to the pool at once.
TEST(FramePool, CrossThreadHandoffThroughARing) {
  const std::uint64_t frames = test::stress_items(200'000);
  FramePool pool(small_settings(6));
  SpscRing<FrameHandle> ring(4);
  Counter ring_drops;
  std::atomic<bool> done{false};
  std::uint64_t received = 0;
  std::uint64_t bad = 0;

  std::thread tracker([&] {
    std::uint64_t last_seq = 0;
    test::Backoff backoff;
    for (;;) {
      const bool finished = done.load(std::memory_order_acquire);
      FrameHandle h;
      if (!ring.try_pop(h)) {
        if (finished) break;
        backoff.pause();
        continue;
      }
      const Frame& f = pool.frame(h);
      const auto tag = static_cast<std::uint8_t>(f.sequence);
      bad += (f.colour.front() != tag || f.colour.back() != tag ||
              f.depth[f.depth.size() / 2] != static_cast<std::uint16_t>(f.sequence) ||
              f.t_ns != static_cast<std::int64_t>(f.sequence) * 50 || f.sequence <= last_seq)
                 ? 1
                 : 0;
      last_seq = f.sequence;
      ++received;
      pool.release(h);
    }
  });

  std::uint64_t pool_drops = 0;
  for (std::uint64_t seq = 1; seq <= frames; ++seq) {
    FrameHandle h = pool.acquire();
    if (!h.valid()) {
      ++pool_drops;
      continue;
    }
    Frame& f = pool.frame(h);
    const auto tag = static_cast<std::uint8_t>(seq);
    f.colour.front() = tag;
    f.colour.back() = tag;
    f.depth[f.depth.size() / 2] = static_cast<std::uint16_t>(seq);
    f.t_ns = static_cast<std::int64_t>(seq) * 50;
    f.sequence = seq;
    push_or_drop(ring, h, ring_drops, [&](FrameHandle& dropped) { pool.release(dropped); });
  }
  done.store(true, std::memory_order_release);
  tracker.join();

  EXPECT_EQ(bad, 0u);
  EXPECT_EQ(received + ring_drops.get() + pool_drops, frames);
  EXPECT_EQ(pool.exhausted(), pool_drops);
  EXPECT_EQ(pool.available(), pool.capacity());
}

// Several threads acquire and release at once (the free list is multi-producer/multi-consumer):
// no slot is ever held by two threads at the same time.
TEST(FramePool, ConcurrentAcquireReleaseNeverSharesASlot) {
  const std::uint64_t rounds = test::stress_items(300'000);
  FramePool pool(small_settings(3));
  std::vector<std::atomic<int>> owner(pool.capacity());
  std::atomic<std::uint64_t> conflicts{0};
  auto worker = [&](int id) {
    for (std::uint64_t i = 0; i < rounds; ++i) {
      const FrameHandle h = pool.acquire();
      if (!h.valid()) continue;
      if (owner[h.index].exchange(id, std::memory_order_relaxed) != 0) conflicts.fetch_add(1);
      pool.frame(h).sequence = i;  // a plain write: TSan flags it if two threads hold the slot
      if (owner[h.index].exchange(0, std::memory_order_relaxed) != id) conflicts.fetch_add(1);
      pool.release(h);
    }
  };
  std::thread a(worker, 1);
  std::thread b(worker, 2);
  std::thread c(worker, 3);
  worker(4);
  a.join();
  b.join();
  c.join();
  EXPECT_EQ(conflicts.load(), 0u);
  EXPECT_EQ(pool.available(), pool.capacity());
}

}  // namespace
}  // namespace vigs::rt
