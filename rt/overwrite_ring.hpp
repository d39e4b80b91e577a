// OverwriteRing<T>: bounded SPSC ring whose producer never fails. When the ring is full, push()
// discards the oldest unread element and counts it. For latest-value streams such as the pose
// output (tracker -> DDS publisher): a slow reader loses old poses, never new ones, and the
// tracker never waits. Capacity 1 makes it a "latest value" mailbox.
//
// T must be trivially copyable (poses, stamps, small fixed structs): the consumer copies an
// element while the producer may be overwriting it, and then discards that copy (see below).
// To keep this free of data races (and TSan-clean) every slot is stored as relaxed atomic 64-bit
// words; T is reassembled from the words with memcpy.
//
// Protocol. write_ and read_ are free-running 64-bit counters; slot = counter & mask.
//  - write_ is written only by the producer (store release).
//  - read_ is changed only by compare-exchange, by both sides: the consumer claims element r by
//    CAS read_ r -> r+1 *after* copying it; the producer evicts element r by the same CAS.
//    Exactly one of them succeeds for each r, and read_ never goes back, so there is no ABA.
// Producer push(v):
//    w = write_; r = read_.load(acquire)
//    if w - r == capacity: CAS(read_, r -> r+1, acq_rel): success = evicted r (count a drop);
//                          failure = the consumer took it, which frees a slot just the same.
//    store v's words into slot w (relaxed); write_.store(w+1, release)
// Consumer try_pop(out):
//    r = read_.load(acquire); w = write_.load(acquire); empty if r == w
//    copy slot r's words (relaxed loads)
//    if CAS(read_, r -> r+1, acq_rel) succeeds the copy is element r, else retry from the top.
// Why a successful CAS means the copy is not torn: the producer only writes slot r & mask for
// element r + capacity, and only after it has observed read_ > r with an acquire load (after its
// own eviction CAS of r, which would have made ours fail, or after seeing our CAS). Our CAS is a
// release, so our word loads happen-before those producer stores and cannot observe them. The
// words of element r itself were published by the producer's release store of write_ > r, which
// we acquired. A failed CAS means the producer evicted r and may be rewriting the slot: the copy
// is thrown away and the loop retries with the new read_.
// Progress: push() is wait-free (at most one CAS). try_pop() is lock-free: it retries only when
// the producer evicted the element being copied, i.e. when the producer is outrunning it.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <type_traits>

#include "rt/cache_line.hpp"

namespace vigs::rt {

template <class T>
class OverwriteRing {
  static_assert(std::is_trivially_copyable_v<T>, "OverwriteRing copies T as raw words");
  static_assert(std::is_default_constructible_v<T>);

 public:
  using value_type = T;

  // capacity: power of two >= 1.
  explicit OverwriteRing(std::size_t capacity) : mask_(capacity - 1) {
    if (capacity == 0 || (capacity & (capacity - 1)) != 0) {
      throw std::invalid_argument("OverwriteRing capacity must be a power of two >= 1");
    }
    slots_ = std::make_unique<Slot[]>(capacity);  // value-initialised words
  }

  OverwriteRing(const OverwriteRing&) = delete;
  OverwriteRing& operator=(const OverwriteRing&) = delete;

  // Producer only. Never fails; returns false when an unread element was overwritten to make room.
  bool push(const T& v) noexcept {
    const std::uint64_t w = write_.load(std::memory_order_relaxed);
    std::uint64_t r = read_.load(std::memory_order_acquire);
    bool kept_all = true;
    if (w - r == capacity()) {
      if (read_.compare_exchange_strong(r, r + 1, std::memory_order_acq_rel,
                                        std::memory_order_acquire)) {
        overwritten_.store(overwritten_.load(std::memory_order_relaxed) + 1,
                           std::memory_order_relaxed);
        kept_all = false;
      }
      // On failure the consumer claimed element r: a slot is free all the same.
    }
    std::array<std::uint64_t, kWords> words{};
    std::memcpy(words.data(), &v, sizeof(T));
    Slot& s = slots_[w & mask_];
    for (std::size_t i = 0; i < kWords; ++i) s.words[i].store(words[i], std::memory_order_relaxed);
    write_.store(w + 1, std::memory_order_release);
    return kept_all;
  }

  // Consumer only. Copies the oldest unread element into `out`; false when empty.
  [[nodiscard]] bool try_pop(T& out) noexcept {
    std::uint64_t r = read_.load(std::memory_order_acquire);
    for (;;) {
      const std::uint64_t w = write_.load(std::memory_order_acquire);
      if (r == w) return false;
      std::array<std::uint64_t, kWords> words;
      const Slot& s = slots_[r & mask_];
      for (std::size_t i = 0; i < kWords; ++i)
        words[i] = s.words[i].load(std::memory_order_relaxed);
      // On failure r is reloaded with the producer's value (acquire) and the copy is discarded.
      if (read_.compare_exchange_strong(r, r + 1, std::memory_order_acq_rel,
                                        std::memory_order_acquire)) {
        std::memcpy(static_cast<void*>(&out), words.data(), sizeof(T));
        return true;
      }
    }
  }

  // Consumer only. Skips to the newest element: pops everything, keeps the last. Elements skipped
  // this way are the consumer's choice and are not counted in overwritten().
  [[nodiscard]] bool try_pop_latest(T& out) noexcept {
    bool any = false;
    while (try_pop(out)) any = true;
    return any;
  }

  // Elements discarded unread by push() so far. Any thread.
  [[nodiscard]] std::uint64_t overwritten() const noexcept {
    return overwritten_.load(std::memory_order_relaxed);
  }
  // Snapshot of the number of unread elements, in [0, capacity()]. Any thread.
  [[nodiscard]] std::size_t size() const noexcept {
    const std::uint64_t r = read_.load(std::memory_order_acquire);
    const std::uint64_t w = write_.load(std::memory_order_acquire);
    const std::uint64_t n = w - r;
    return n > capacity() ? capacity() : static_cast<std::size_t>(n);
  }
  [[nodiscard]] bool empty() const noexcept { return size() == 0; }
  [[nodiscard]] std::size_t capacity() const noexcept { return mask_ + 1; }

 private:
  static constexpr std::size_t kWords = (sizeof(T) + 7) / 8;
  struct Slot {
    std::array<std::atomic<std::uint64_t>, kWords> words{};
  };
  static_assert(std::atomic<std::uint64_t>::is_always_lock_free);

  // write_ and the drop count are written by the producer only; read_ by both (CAS), so it sits
  // alone. Slots are read-mostly shared data behind a pointer that never changes.
  alignas(kCacheLineSize) std::atomic<std::uint64_t> write_{0};
  std::atomic<std::uint64_t> overwritten_{0};
  alignas(kCacheLineSize) std::atomic<std::uint64_t> read_{0};
  alignas(kCacheLineSize) const std::size_t mask_;
  std::unique_ptr<Slot[]> slots_;
};

}  // namespace vigs::rt
