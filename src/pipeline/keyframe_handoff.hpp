#pragma once
// KeyframeHandoff: the tracker -> mapper keyframe queue of the live pipeline, without any
// allocation on the tracker's side. A fixed number of slots is made at start-up, each with a
// tracking::Keyframe whose vectors are reserved for a whole frame's points; the tracker copies
// its keyframe into a free slot (vector copy-assignment reuses the capacity) together with the
// frame's FramePool handle (retained), and queues the slot index. The mapper side builds its
// own MapperKeyframe from the slot (allocating, on the mapper thread), releases the frame and
// hands the slot back.
//
// Bound and policy: at most `slots` keyframes are in flight. When none is free (the mapper is
// that far behind) the tracker drops the newest keyframe and counts it (dropped()); in lockstep
// it waits for the mapper instead. The end of the stream is the index kEnd.
//
// Threads: one tracker thread (acquire, publish, publish_end), one mapper thread (next,
// give_back); the constructor fills the free list before either starts.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rt/counters.hpp"
#include "rt/frame_pool.hpp"
#include "rt/spsc_ring.hpp"
#include "tracking/gaussian_cloud.hpp"

namespace vigs::pipeline {

struct KeyframeSlot {
  tracking::Keyframe keyframe;
  rt::FrameHandle frame;  ///< the keyframe's image, retained for the mapper
  /// The tracker restarted its map at this keyframe: no odometry joins it to the previous one
  /// (the loop closer's graph, tracking/loop_closure.hpp).
  bool after_restart = false;
};

class KeyframeHandoff {
 public:
  static constexpr std::uint32_t kEnd = 0xFFFF'FFFFu;

  /// `slots` >= 1 (a power of two), `points` the most points a keyframe can have.
  KeyframeHandoff(std::size_t slots, std::size_t points);

  // ---- tracker side ----
  /// A free slot, or nullptr when all are in flight.
  [[nodiscard]] KeyframeSlot* acquire() noexcept;
  /// Queues a slot from acquire() (never fails: the queue holds every slot).
  void publish(KeyframeSlot* slot) noexcept;
  /// Queues the end-of-stream marker; false while the queue is full (retry).
  [[nodiscard]] bool publish_end() noexcept { return full_.try_push(kEnd); }
  void count_drop() noexcept { dropped_.add(); }

  // ---- mapper side ----
  /// The next queued slot index (kEnd at the end of the stream), or false when none.
  [[nodiscard]] bool next(std::uint32_t& index) noexcept { return full_.try_pop(index); }
  [[nodiscard]] KeyframeSlot& slot(std::uint32_t index) noexcept { return slots_[index]; }
  void give_back(std::uint32_t index) noexcept;

  [[nodiscard]] std::size_t capacity() const noexcept { return slots_.size(); }
  [[nodiscard]] std::size_t queued() const noexcept { return full_.size(); }
  [[nodiscard]] std::uint64_t dropped() const noexcept { return dropped_.get(); }

 private:
  std::vector<KeyframeSlot> slots_;
  rt::SpscRing<std::uint32_t> free_;  // mapper -> tracker
  rt::SpscRing<std::uint32_t> full_;  // tracker -> mapper (one extra place for kEnd)
  rt::SingleWriterCounter dropped_;
};

}  // namespace vigs::pipeline
