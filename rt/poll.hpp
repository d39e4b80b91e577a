#pragma once
// Polls `ready` every `step_ns` until it holds or `within_ns` has passed (CLOCK_MONOTONIC), for
// the non-real-time start-up and shut-down paths that wait on another thread's progress; and a
// sleep until a host time that a stop request cuts short (threads pacing a replay).
#include <algorithm>
#include <cstdint>
#include <stop_token>

#include "rt/clock.hpp"

namespace vigs::rt {

/// True when `ready()` held before the deadline.
template <class Pred>
bool poll_until(Pred&& ready, std::int64_t within_ns, std::int64_t step_ns = ms_to_ns(1)) {
  const std::int64_t give_up = monotonic_ns() + within_ns;
  while (!ready()) {
    if (monotonic_ns() >= give_up) return false;
    sleep_until_ns(monotonic_ns() + step_ns);
  }
  return true;
}

/// Sleeps until host time `deadline_ns` in steps of at most `step_ns`, checking `stop` before
/// each: true when the deadline came, false as soon as a stop was requested.
inline bool sleep_until_or_stop(std::int64_t deadline_ns, const std::stop_token& stop,
                                std::int64_t step_ns) noexcept {
  while (!stop.stop_requested()) {
    const std::int64_t now_ns = monotonic_ns();
    if (now_ns >= deadline_ns) return true;
    sleep_until_ns(std::min(deadline_ns, now_ns + step_ns));
  }
  return false;
}

}  // namespace vigs::rt
