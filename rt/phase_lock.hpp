// PhaseLock: keeps a fixed-rate consumer's ticks just after the items it consumes arrive.
//
// A camera delivers a frame every period P at a phase the tracker task does not choose. A
// fixed-rate tick at an arbitrary phase lets each frame wait in the ring for up to P (P/2 on
// average) before it is even looked at, and that wait is pure pose latency. The task keeps its
// fixed rate (rt::PeriodicTask's grid) but lets this lock slide the grid: every tick that takes
// a fresh item reports (wake - arrival), and the lock answers the shift of the next deadline
// that moves the wake toward arrival + lead:
//
//   e     = wrap(wake - arrival - lead) into [-P/2, P/2)
//   shift = -gain * e
//
// A first-order loop: with 0 < gain < 2 the error shrinks by |1 - gain| per tick. The wrap
// makes a frame that arrived just after the previous tick (lag close to P) read as "the tick
// is a little early" (a small later shift), not "the tick is P late". `lead` is the margin
// for the arrival's jitter: a frame that arrives more than `lead` late is taken one tick
// later, which the lock then answers with a small later shift, so the ticks settle where
// frames are rarely missed. Pure arithmetic on CLOCK_MONOTONIC nanoseconds: no clock read, no
// allocation (tests drive it with made-up times).
#pragma once

#include <cstdint>

namespace vigs::rt {

struct PhaseLockSettings {
  std::int64_t period_ns = 0;  ///< the task's period (> 0)
  std::int64_t lead_ns = 0;    ///< target wake - arrival
  double gain = 0.5;           ///< fraction of the phase error corrected per tick, (0, 2)
};

class PhaseLock {
 public:
  explicit constexpr PhaseLock(const PhaseLockSettings& s) noexcept : s_(s) {}

  /// Phase error of a tick that woke at `wake_ns` and took an item that arrived at
  /// `arrival_ns`, wrapped into [-P/2, P/2).
  [[nodiscard]] constexpr std::int64_t error_ns(std::int64_t wake_ns,
                                                std::int64_t arrival_ns) const noexcept {
    const std::int64_t p = s_.period_ns;
    std::int64_t e = (wake_ns - arrival_ns - s_.lead_ns) % p;  // in (-P, P)
    if (e >= p / 2) e -= p;
    if (e < -p / 2) e += p;
    return e;
  }

  /// The shift to add to the next deadline (rt::PeriodicTask::shift_next_deadline).
  [[nodiscard]] constexpr std::int64_t shift_ns(std::int64_t wake_ns,
                                                std::int64_t arrival_ns) const noexcept {
    return static_cast<std::int64_t>(-s_.gain * static_cast<double>(error_ns(wake_ns, arrival_ns)));
  }

  [[nodiscard]] constexpr const PhaseLockSettings& settings() const noexcept { return s_; }

 private:
  PhaseLockSettings s_;
};

}  // namespace vigs::rt
