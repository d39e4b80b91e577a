// SpscRing<T>: bounded, lock-free, single-producer / single-consumer ring.
//
// Full-ring policy, per stream (the producer is a real-time thread and never blocks):
//  | stream                        | ring            | when full                                  |
//  |-------------------------------|-----------------|--------------------------------------------|
//  | IMU samples (imu -> tracker)  | SpscRing        | drop the newest sample and count it        |
//  |                               |                 | (push_or_drop, rt/queue_policy.hpp)        |
//  | frame handles (rgbd->tracker) | SpscRing        | drop the newest frame, count it, and give  |
//  |                               |                 | its handle back to the FramePool at once   |
//  | edge stamps (gpio -> tracker) | SpscRing        | drop the newest stamp and count it         |
//  | pose output (tracker -> dds)  | OverwriteRing   | overwrite the oldest unread pose, count it |
//  |                               |                 | (rt/overwrite_ring.hpp)                    |
//  | keyframes (tracker -> mapper) | SpscRing        | bounded: the mapper keeps at most `bound`  |
//  |                               |                 | unprocessed keyframes and merges or skips  |
//  |                               |                 | the oldest extra ones, counting them       |
//  |                               |                 | (trim_oldest); if the ring itself is full  |
//  |                               |                 | (mapper stalled) the newest is dropped     |
//  |                               |                 | and counted                                |
// How a stream ends: the producer pushes its element type's end-of-stream marker (retrying, not
// dropping, since shutdown is not real-time) and the consumer drains until it sees it. Elements
// still queued when a ring is destroyed are destroyed with it.
//
// Design (after rigtorp/SPSCQueue and the Linux kfifo, written anew):
//  - write_ and read_ are free-running 64-bit counters (slot = counter & mask), so full is
//    `write - read == capacity` and no slot is wasted. 2^64 pushes never wrap in practice.
//  - The producer's line holds write_ and its cached copy of read_; the consumer's line holds
//    read_ and its cached copy of write_. Each side re-reads the peer's index (acquire) only when
//    its cached copy says full/empty, so while the ring is neither, a push or pop touches no
//    line the other side writes except the slot itself.
//  - Publication is one release store (write_ after constructing the element, read_ after
//    destroying it) paired with the peer's acquire load. No fences, no RMW instructions.
//  - Capacity is a runtime power of two (checked at construction; the constructor is the only
//    place that allocates, so configure it at start-up).
//
// Thread rules: exactly one thread calls the producer functions (try_push, try_emplace), exactly
// one (possibly other) thread calls the consumer functions (front, pop, try_pop). size() and
// empty() may be called from either side or a third thread and are approximate snapshots.
#pragma once

#include <atomic>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <new>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "rt/cache_line.hpp"

namespace vigs::rt {

template <class T>
class SpscRing {
  static_assert(std::is_nothrow_destructible_v<T>, "pop() and ~SpscRing destroy elements");

 public:
  using value_type = T;

  // capacity: number of elements the ring can hold; must be a power of two >= 1.
  explicit SpscRing(std::size_t capacity) : mask_(capacity - 1), slots_(allocate(capacity)) {}

  ~SpscRing() {
    const std::uint64_t w = producer_.write.load(std::memory_order_acquire);
    for (std::uint64_t r = consumer_.read.load(std::memory_order_relaxed); r != w; ++r) {
      slot(r)->~T();
    }
    ::operator delete (static_cast<void*>(slots_), std::align_val_t{kStorageAlign});
  }

  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;
  SpscRing(SpscRing&&) = delete;
  SpscRing& operator=(SpscRing&&) = delete;

  // ---- producer side ----

  // Constructs an element in place. Returns false (and constructs nothing) when full.
  template <class... Args>
  [[nodiscard]] bool try_emplace(Args&&... args) noexcept(
      std::is_nothrow_constructible_v<T, Args&&...>) {
    static_assert(std::is_constructible_v<T, Args&&...>);
    const std::uint64_t w = producer_.write.load(std::memory_order_relaxed);
    if (w - producer_.read_cache == capacity()) {
      producer_.read_cache = consumer_.read.load(std::memory_order_acquire);
      if (w - producer_.read_cache == capacity()) return false;
    }
    ::new (static_cast<void*>(slot(w))) T(std::forward<Args>(args)...);
    producer_.write.store(w + 1, std::memory_order_release);
    return true;
  }

  [[nodiscard]] bool try_push(const T& v) noexcept(std::is_nothrow_copy_constructible_v<T>) {
    return try_emplace(v);
  }
  [[nodiscard]] bool try_push(T&& v) noexcept(std::is_nothrow_move_constructible_v<T>) {
    return try_emplace(std::move(v));
  }

  // ---- consumer side ----

  // Oldest element, or nullptr when empty. Stays valid until pop().
  [[nodiscard]] T* front() noexcept {
    const std::uint64_t r = consumer_.read.load(std::memory_order_relaxed);
    if (r == consumer_.write_cache) {
      consumer_.write_cache = producer_.write.load(std::memory_order_acquire);
      if (r == consumer_.write_cache) return nullptr;
    }
    return slot(r);
  }

  // Destroys the oldest element. Precondition: front() returned non-null since the last pop().
  void pop() noexcept {
    const std::uint64_t r = consumer_.read.load(std::memory_order_relaxed);
    assert(r != consumer_.write_cache && "pop() on an empty SpscRing");
    slot(r)->~T();
    consumer_.read.store(r + 1, std::memory_order_release);
  }

  // Moves the oldest element into `out`. Returns false when empty.
  [[nodiscard]] bool try_pop(T& out) noexcept(std::is_nothrow_move_assignable_v<T>) {
    T* p = front();
    if (p == nullptr) return false;
    out = std::move(*p);
    pop();
    return true;
  }

  [[nodiscard]] std::optional<T> try_pop() noexcept(std::is_nothrow_move_constructible_v<T>) {
    T* p = front();
    if (p == nullptr) return std::nullopt;
    std::optional<T> out(std::move(*p));
    pop();
    return out;
  }

  // ---- either side ----

  // Number of queued elements, in [0, capacity()]. A snapshot: exact only on a quiet ring.
  [[nodiscard]] std::size_t size() const noexcept {
    // Read `read` first: `write` can then only be >= it. The difference may briefly exceed the
    // capacity (read is older than write), so clamp.
    const std::uint64_t r = consumer_.read.load(std::memory_order_acquire);
    const std::uint64_t w = producer_.write.load(std::memory_order_acquire);
    const std::uint64_t n = w - r;
    return n > capacity() ? capacity() : static_cast<std::size_t>(n);
  }
  [[nodiscard]] bool empty() const noexcept { return size() == 0; }
  [[nodiscard]] std::size_t capacity() const noexcept { return mask_ + 1; }

 private:
  static constexpr std::size_t kStorageAlign = alignof(T) > kCacheLineSize ? alignof(T)
                                                                           : kCacheLineSize;

  struct alignas(kCacheLineSize) ProducerLine {
    std::atomic<std::uint64_t> write{0};
    std::uint64_t read_cache = 0;  // producer's last view of consumer_.read
  };
  struct alignas(kCacheLineSize) ConsumerLine {
    std::atomic<std::uint64_t> read{0};
    std::uint64_t write_cache = 0;  // consumer's last view of producer_.write
  };
  static_assert(sizeof(ProducerLine) == kCacheLineSize && alignof(ProducerLine) == kCacheLineSize);
  static_assert(sizeof(ConsumerLine) == kCacheLineSize && alignof(ConsumerLine) == kCacheLineSize);
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free);

  // Slots start on their own cache line (and the allocation is rounded up to whole lines), so no
  // element shares a line with the indices or with unrelated heap data.
  static T* allocate(std::size_t capacity) {
    if (capacity == 0 || (capacity & (capacity - 1)) != 0) {
      throw std::invalid_argument("SpscRing capacity must be a power of two >= 1");
    }
    const std::size_t bytes =
        (capacity * sizeof(T) + kStorageAlign - 1) / kStorageAlign * kStorageAlign;
    return static_cast<T*>(::operator new (bytes, std::align_val_t{kStorageAlign}));
  }

  T* slot(std::uint64_t i) const noexcept { return slots_ + (i & mask_); }

  ProducerLine producer_;
  ConsumerLine consumer_;
  // Written once at construction, read by both sides: on a line of its own.
  alignas(kCacheLineSize) const std::size_t mask_;
  T* const slots_;
};

}  // namespace vigs::rt
