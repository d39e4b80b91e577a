// Cheap event counters for real-time threads: drops, overruns, exhausted pools, queue depths.
//
// All operations are relaxed atomics: a counter orders nothing, it only has to be exact and
// readable from another thread (status publisher, exit report) without a data race.
//  - Counter: any number of writers (fetch_add). Use for events counted from several threads.
//  - SingleWriterCounter: one writing thread (load + store, no locked read-modify-write), readable
//    from any thread. Cheaper on the hot path; two writers would lose counts.
//  - HighWaterMark: single writer, keeps the maximum observed value (e.g. ring depth).
//  - Padded<C>: C alone on its cache line, for counters written by different threads that would
//    otherwise sit side by side in one struct.
#pragma once

#include <atomic>
#include <cstdint>

#include "rt/cache_line.hpp"

namespace vigs::rt {

class Counter {
 public:
  void add(std::uint64_t n = 1) noexcept { value_.fetch_add(n, std::memory_order_relaxed); }
  [[nodiscard]] std::uint64_t get() const noexcept {
    return value_.load(std::memory_order_relaxed);
  }
  // Not for concurrent use with add() if the caller needs exact totals across the reset.
  void reset() noexcept { value_.store(0, std::memory_order_relaxed); }

 private:
  std::atomic<std::uint64_t> value_{0};
};

class SingleWriterCounter {
 public:
  // Only the owning thread may call add().
  void add(std::uint64_t n = 1) noexcept {
    value_.store(value_.load(std::memory_order_relaxed) + n, std::memory_order_relaxed);
  }
  [[nodiscard]] std::uint64_t get() const noexcept {
    return value_.load(std::memory_order_relaxed);
  }
  void reset() noexcept { value_.store(0, std::memory_order_relaxed); }

 private:
  std::atomic<std::uint64_t> value_{0};
};

class HighWaterMark {
 public:
  // Only the owning thread may call observe().
  void observe(std::uint64_t v) noexcept {
    if (v > value_.load(std::memory_order_relaxed)) value_.store(v, std::memory_order_relaxed);
  }
  [[nodiscard]] std::uint64_t get() const noexcept {
    return value_.load(std::memory_order_relaxed);
  }
  void reset() noexcept { value_.store(0, std::memory_order_relaxed); }

 private:
  std::atomic<std::uint64_t> value_{0};
};

template <class C>
struct alignas(kCacheLineSize) Padded : C {};

using PaddedCounter = Padded<Counter>;
using PaddedSingleWriterCounter = Padded<SingleWriterCounter>;

static_assert(std::atomic<std::uint64_t>::is_always_lock_free);
static_assert(sizeof(PaddedCounter) == kCacheLineSize && alignof(PaddedCounter) == kCacheLineSize);

}  // namespace vigs::rt
