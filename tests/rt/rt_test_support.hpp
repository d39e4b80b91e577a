// Helpers shared by the rt tests: sanitizer detection and stress sizes.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <string>
#include <thread>

#if defined(__SANITIZE_THREAD__)
#define VIGS_RT_TEST_TSAN 1
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
#define VIGS_RT_TEST_TSAN 1
#endif
#endif
#ifndef VIGS_RT_TEST_TSAN
#define VIGS_RT_TEST_TSAN 0
#endif

namespace vigs::rt::test {

inline constexpr bool kUnderTsan = VIGS_RT_TEST_TSAN != 0;

// Items for a two-thread stress test: `full` normally, full / 10 under ThreadSanitizer (which
// slows every atomic access by an order of magnitude or more), or VIGS_RT_STRESS_ITEMS if set.
inline std::uint64_t stress_items(std::uint64_t full) {
  if (const char* env = std::getenv("VIGS_RT_STRESS_ITEMS"); env != nullptr && *env != '\0') {
    return std::stoull(env);
  }
  return kUnderTsan ? full / 10 : full;
}

// Spin-wait helper for the stress tests: spins briefly, then yields, so that a busy CI machine
// (more runnable threads than cores) does not stall a test whose peer thread is descheduled.
class Backoff {
 public:
  void pause() {
    if (++spins_ >= 64) {
      spins_ = 0;
      std::this_thread::yield();
    }
  }
  void reset() { spins_ = 0; }

 private:
  int spins_ = 0;
};

}  // namespace vigs::rt::test
