#pragma once
// Polls `ready` every `step_ns` until it holds or `within_ns` has passed (CLOCK_MONOTONIC), for
// the non-real-time start-up and shut-down paths that wait on another thread's progress.
#include <cstdint>

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

}  // namespace vigs::rt
