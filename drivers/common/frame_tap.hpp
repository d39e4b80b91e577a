// FrameTap: a camera driver's second output, the recorder's ring. The driver offers it every pair
// it formed, before the main ring: the slot gets one more reference (FramePool::retain) and the
// handle goes into the tap; a full tap drops it, gives the reference back and counts it. The
// driver never waits for the recorder, and the main ring's policy is unchanged. Size the pool for
// the tap too (its capacity more slots).
#pragma once

#include "rt/counters.hpp"
#include "rt/frame_pool.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::drivers {

class FrameTap {
 public:
  void set(rt::SpscRing<rt::FrameHandle>* ring) noexcept { ring_ = ring; }
  [[nodiscard]] bool enabled() const noexcept { return ring_ != nullptr; }
  /// Driver thread: offers a handle the driver holds; never blocks.
  void offer(rt::FramePool& pool, rt::FrameHandle h) noexcept {
    if (ring_ == nullptr) return;
    pool.retain(h);
    if (!ring_->try_push(h)) {
      pool.release(h);
      dropped_.add();
    }
  }
  [[nodiscard]] std::uint64_t dropped() const noexcept { return dropped_.get(); }
  void reset() noexcept { dropped_.reset(); }

 private:
  rt::SpscRing<rt::FrameHandle>* ring_ = nullptr;
  rt::SingleWriterCounter dropped_;
};

}  // namespace vigs::drivers
