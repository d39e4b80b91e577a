#include "rt/clock.hpp"

#include <cerrno>

namespace vigs::rt {

std::int64_t monotonic_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return from_timespec(ts);
}

void sleep_until_ns(std::int64_t deadline_ns) noexcept {
  const timespec deadline = to_timespec(deadline_ns);
  // clock_nanosleep returns the error number (not -1/errno). With TIMER_ABSTIME a signal simply
  // means "sleep again until the same deadline"; no remaining-time bookkeeping is needed.
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
  }
}

}  // namespace vigs::rt
