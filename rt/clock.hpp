// Monotonic time in int64 nanoseconds, the one clock every VIGS stamp (`t_ns`) and deadline uses.
//
// CLOCK_MONOTONIC never jumps with NTP or manual clock changes, and it is the clock that
// clock_nanosleep(TIMER_ABSTIME) deadlines in rt/periodic_task.hpp are expressed in. int64 ns
// covers ±292 years, so plain subtraction of two stamps never overflows.
#pragma once

#include <cstdint>
#include <ctime>

namespace vigs::rt {

inline constexpr std::int64_t kNsPerUs = 1'000;
inline constexpr std::int64_t kNsPerMs = 1'000'000;
inline constexpr std::int64_t kNsPerS = 1'000'000'000;

// Current CLOCK_MONOTONIC time in nanoseconds. Real-time safe (vDSO, no syscall on x86-64/ARMv8).
[[nodiscard]] std::int64_t monotonic_ns() noexcept;

// Sleeps until the absolute CLOCK_MONOTONIC time `deadline_ns` (retrying on EINTR). Returns at
// once when the deadline has passed.
void sleep_until_ns(std::int64_t deadline_ns) noexcept;

[[nodiscard]] constexpr std::int64_t us_to_ns(std::int64_t us) noexcept {
  return us * kNsPerUs;
}
[[nodiscard]] constexpr std::int64_t ms_to_ns(std::int64_t ms) noexcept {
  return ms * kNsPerMs;
}
[[nodiscard]] constexpr std::int64_t s_to_ns(std::int64_t s) noexcept {
  return s * kNsPerS;
}
// Seconds as double to ns, rounded to nearest (for config values such as `period_s: 0.05`).
[[nodiscard]] constexpr std::int64_t s_to_ns(double s) noexcept {
  const double ns = s * static_cast<double>(kNsPerS);
  return static_cast<std::int64_t>(ns < 0.0 ? ns - 0.5 : ns + 0.5);
}

[[nodiscard]] constexpr double ns_to_us(std::int64_t ns) noexcept {
  return static_cast<double>(ns) / static_cast<double>(kNsPerUs);
}
[[nodiscard]] constexpr double ns_to_ms(std::int64_t ns) noexcept {
  return static_cast<double>(ns) / static_cast<double>(kNsPerMs);
}
[[nodiscard]] constexpr double ns_to_s(std::int64_t ns) noexcept {
  return static_cast<double>(ns) / static_cast<double>(kNsPerS);
}

// timespec <-> ns. `to_timespec` handles negative values (tv_nsec stays in [0, 1e9)).
[[nodiscard]] constexpr timespec to_timespec(std::int64_t ns) noexcept {
  std::int64_t sec = ns / kNsPerS;
  std::int64_t rem = ns % kNsPerS;
  if (rem < 0) {
    rem += kNsPerS;
    sec -= 1;
  }
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(sec);
  ts.tv_nsec = static_cast<long>(rem);
  return ts;
}
[[nodiscard]] constexpr std::int64_t from_timespec(const timespec& ts) noexcept {
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerS + static_cast<std::int64_t>(ts.tv_nsec);
}

}  // namespace vigs::rt
