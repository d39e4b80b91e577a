#include "rt/phase_lock.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>

#include "rt/clock.hpp"

namespace vigs::rt {
namespace {

constexpr std::int64_t kPeriod = 50'000'000;  // 20 Hz camera
constexpr std::int64_t kLead = 2'000'000;

PhaseLock lock(double gain = 0.5) {
  return PhaseLock({.period_ns = kPeriod, .lead_ns = kLead, .gain = gain});
}

TEST(PhaseLock, ErrorIsWrappedIntoHalfAPeriod) {
  const PhaseLock pl = lock();
  EXPECT_EQ(pl.error_ns(1'000'000'000 + kLead, 1'000'000'000), 0);
  EXPECT_EQ(pl.error_ns(1'000'000'000 + kLead + 10'000'000, 1'000'000'000), 10'000'000);
  // A frame that arrived just after the previous tick: lag close to a period reads as a tick
  // a little early (wrapped), not a period late.
  EXPECT_EQ(pl.error_ns(1'000'000'000 + kPeriod - 1'000'000, 1'000'000'000), -kLead - 1'000'000);
  EXPECT_LT(pl.shift_ns(1'000'000'000 + 20'000'000, 1'000'000'000), 0);  // tick earlier
  EXPECT_GT(pl.shift_ns(1'000'000'000 + 49'000'000, 1'000'000'000), 0);  // tick later
  // Several periods of lag (frames skipped) still give the phase.
  EXPECT_EQ(pl.error_ns(1'000'000'000 + 3 * kPeriod + kLead + 5, 1'000'000'000), 5);
}

/// A camera and a fixed-rate task simulated in integer time: frames arrive every period at
/// `phase` (plus jitter); the task ticks on its grid, takes the newest frame that has arrived,
/// and applies the lock's shift. Returns the mean lag (tick - arrival) over the last
/// `measure` frames taken and counts frames the tick took one period late.
struct SimRun {
  double mean_lag_ns = 0;
  int late = 0;  ///< lag over a quarter period
};

SimRun simulate(const PhaseLock& pl, std::int64_t phase_ns, std::int64_t jitter_ns, int ticks,
                int measure, bool lock_on = true) {
  std::int64_t deadline = 0;
  std::int64_t last_taken = -1;
  SimRun r;
  long sum = 0, n = 0;
  std::uint32_t rng = 12345;
  for (int k = 0; k < ticks; ++k) {
    // Newest frame that arrived by the tick (frame j arrives at phase + j P + jitter_j, with a
    // deterministic jitter in [0, jitter]).
    const std::int64_t j = (deadline - phase_ns) / kPeriod + 1;
    std::int64_t taken = -1, arrival = 0;
    for (std::int64_t c = j; c >= j - 2 && c >= 0; --c) {
      rng = rng * 1664525u + 1013904223u;
      const std::int64_t a =
          phase_ns + c * kPeriod + (jitter_ns > 0 ? static_cast<std::int64_t>(rng % jitter_ns) : 0);
      if (a <= deadline) {
        taken = c;
        arrival = a;
        break;
      }
    }
    std::int64_t shift = 0;
    if (taken > last_taken && taken >= 0) {
      last_taken = taken;
      const std::int64_t lag = deadline - arrival;
      if (k >= ticks - measure) {
        sum += lag;
        ++n;
        if (lag > kPeriod / 4) ++r.late;
      }
      if (lock_on) shift = pl.shift_ns(deadline, arrival);
    }
    if (shift > kPeriod / 2) shift = kPeriod / 2;
    if (shift < -kPeriod / 2) shift = -kPeriod / 2;
    deadline += kPeriod + shift;
  }
  r.mean_lag_ns = n > 0 ? static_cast<double>(sum) / static_cast<double>(n) : 0;
  return r;
}

TEST(PhaseLock, TicksSettleJustAfterTheArrivalFromAnyPhase) {
  for (std::int64_t phase :
       {1'000'000, 13'000'000, 24'000'000, 26'000'000, 40'000'000, 49'000'000}) {
    const SimRun off = simulate(lock(), phase, 0, 200, 100, false);
    const SimRun on = simulate(lock(), phase, 0, 200, 100);
    SCOPED_TRACE(phase);
    EXPECT_NEAR(on.mean_lag_ns, static_cast<double>(kLead), 0.1e6);
    EXPECT_EQ(on.late, 0);
    // Without the lock the lag is wherever the phase put it (here: P - phase).
    EXPECT_NEAR(off.mean_lag_ns, static_cast<double>(kPeriod - phase % kPeriod), 1.0);
  }
}

TEST(PhaseLock, JitteryArrivalsAreRarelyMissed) {
  // Arrivals jitter by up to 3 ms: the lock must not chase every frame into the next period.
  const SimRun on = simulate(lock(), 31'000'000, 3'000'000, 2000, 1000);
  EXPECT_LT(on.mean_lag_ns, 8e6);
  EXPECT_LT(on.late, 100);  // under 10 % taken a period late
  const SimRun off = simulate(lock(), 31'000'000, 3'000'000, 2000, 1000, false);
  EXPECT_GT(off.mean_lag_ns, 15e6);
}

}  // namespace
}  // namespace vigs::rt
