// FramePool: N preallocated RGB-D image slots handed out as small FrameHandles.
//
// Rings carry 4-byte FrameHandles instead of images, so nothing allocates or copies per frame.
// All memory is allocated and touched (pre-faulted) in the constructor; afterwards acquire() and
// release() only move indices.
//
// Threads: acquire(), retain() and release() are lock-free and may be called from ANY thread
// (the driver acquires; the tracker, the recorder, or the driver itself when a ring is full,
// release). Free slots form a Treiber stack whose head carries a 32-bit tag, bumped on every
// change, so a concurrent pop/push cannot suffer ABA. Each slot has a reference count: acquire()
// gives 1, retain() adds one for each extra consumer (the driver retains before pushing the same
// handle to a second ring), release() drops one, and the last release returns the slot.
// Data: the holder of a reference may read the slot; only the thread that acquired it writes it,
// before publishing the handle through a ring (whose release/acquire makes the writes visible).
// The last release happens-before the next acquire of that slot (acq_rel refcount, release push,
// acquire pop), so the next writer cannot race a late reader.
// Exhaustion: acquire() returns an invalid handle and counts the event (exhausted()); the driver
// then drops the incoming frame and counts that too. Size the pool for every frame that can be
// alive at once: 1 being filled + ring capacities + 1 per consumer.
#pragma once

#include <atomic>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>

#include "rt/cache_line.hpp"
#include "rt/counters.hpp"

namespace vigs::rt {

struct FramePoolSettings {
  std::uint32_t slots = 8;            // frames that can be alive at once
  std::uint32_t width = 640;          // px
  std::uint32_t height = 480;         // px
  std::uint32_t colour_channels = 3;  // bytes per colour pixel: 3 = rgb8, 1 = mono8
};

struct FrameHandle {
  static constexpr std::uint32_t kInvalidIndex = 0xFFFF'FFFFu;
  std::uint32_t index = kInvalidIndex;

  [[nodiscard]] constexpr bool valid() const noexcept { return index != kInvalidIndex; }
  friend constexpr bool operator==(FrameHandle, FrameHandle) = default;
};
static_assert(sizeof(FrameHandle) == 4);

// One slot. Buffers are row-major without row padding, and start on a cache line.
struct Frame {
  std::span<std::uint8_t> colour;  // width * height * colour_channels bytes
  std::span<std::uint16_t> depth;  // width * height raw 16-bit depth (16UC1); unit set by the
                                   // camera model (OpenNI2: mm); 0 = no measurement
  std::int64_t t_ns = 0;           // CLOCK_MONOTONIC capture time
  std::int64_t arrival_ns = 0;     // CLOCK_MONOTONIC when the driver handed it to its ring
                                   // (pose latency; the tracker's phase lock, rt/phase_lock.hpp)
  std::uint64_t sequence = 0;      // driver frame counter
};

class FramePool {
 public:
  // Allocates and zero-fills every slot (std::invalid_argument on 0 slots or 0 pixels).
  explicit FramePool(const FramePoolSettings& settings);
  ~FramePool();
  FramePool(const FramePool&) = delete;
  FramePool& operator=(const FramePool&) = delete;

  // A free slot with reference count 1, or an invalid handle when none is free (counted).
  [[nodiscard]] FrameHandle acquire() noexcept;
  // Adds a reference to a handle the caller already holds.
  void retain(FrameHandle h) noexcept;
  // Drops a reference; the slot becomes free when the count reaches zero. Invalid handles are
  // ignored, so `pool.release(pool.acquire())` is always safe.
  void release(FrameHandle h) noexcept;

  // The slot behind a valid handle the caller holds.
  [[nodiscard]] Frame& frame(FrameHandle h) noexcept {
    assert(h.index < settings_.slots);
    return frames_[h.index];
  }
  [[nodiscard]] const Frame& frame(FrameHandle h) const noexcept {
    assert(h.index < settings_.slots);
    return frames_[h.index];
  }

  [[nodiscard]] const FramePoolSettings& settings() const noexcept { return settings_; }
  [[nodiscard]] std::size_t capacity() const noexcept { return settings_.slots; }
  // Free slots right now (a snapshot).
  [[nodiscard]] std::size_t available() const noexcept {
    return free_count_.load(std::memory_order_relaxed);
  }
  // acquire() calls that found the pool empty.
  [[nodiscard]] std::uint64_t exhausted() const noexcept { return exhausted_.get(); }

 private:
  static constexpr std::uint32_t kNil = FrameHandle::kInvalidIndex;
  static std::uint64_t pack(std::uint32_t index, std::uint32_t tag) noexcept {
    return (static_cast<std::uint64_t>(tag) << 32) | index;
  }
  void push_free(std::uint32_t index) noexcept;

  FramePoolSettings settings_;
  std::unique_ptr<Frame[]> frames_;
  std::unique_ptr<std::atomic<std::uint32_t>[]> refs_;
  std::unique_ptr<std::atomic<std::uint32_t>[]> next_free_;
  std::uint8_t* colour_storage_ = nullptr;
  std::uint16_t* depth_storage_ = nullptr;
  std::size_t colour_bytes_ = 0;  // whole allocation sizes
  std::size_t depth_bytes_ = 0;

  alignas(kCacheLineSize) std::atomic<std::uint64_t> free_head_{pack(kNil, 0)};  // tag:index
  std::atomic<std::size_t> free_count_{0};
  alignas(kCacheLineSize) Counter exhausted_;
};

}  // namespace vigs::rt
