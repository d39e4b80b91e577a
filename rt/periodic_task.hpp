// PeriodicTask: runs a callable at a fixed rate on its own RtThread.
//
// Deadlines are absolute CLOCK_MONOTONIC times, deadline_k = start + k * period, slept to with
// clock_nanosleep(TIMER_ABSTIME), so the rate does not drift with the body's run time or with
// wake-up latency. The first cycle runs one period after start().
// Overrun policy: a cycle that finishes after its next deadline is an overrun. By default
// (Overrun::kSkip) the task does not try to catch up with back-to-back cycles; it skips to the
// next deadline still in the future and counts every deadline it skipped (missed_deadlines). So
// cycles() + missed_deadlines() tracks elapsed / period however loaded the machine is, and the
// schedule stays on the original grid. Overrun::kRunAtOnce instead starts the next cycle as soon
// as the late one ends and moves the grid there: for a best-effort task whose period only paces
// it while it has nothing to do (the mapper), waiting for the grid would idle it for half a
// period on average after every long cycle.
// Every cycle records the wake-up jitter (actual wake - deadline) and the cycle time (body run
// time, wake to end) in histograms. The loop itself allocates nothing, takes no lock and logs
// nothing; the body decides what it does.
// Stopping: request_stop() sets the flag (any thread, also from inside the body); the loop exits
// before the next body call, so stop() returns within one period plus one body run.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <concepts>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <stop_token>
#include <string>
#include <utility>

#include "rt/counters.hpp"
#include "rt/latency_histogram.hpp"
#include "rt/rt_thread.hpp"
#include "rt/thread_table.hpp"

namespace vigs::rt {

class PeriodicTask {
 public:
  struct Cycle {
    std::int64_t deadline_ns;  // CLOCK_MONOTONIC deadline this cycle was scheduled for
    std::int64_t wake_ns;      // when the thread actually woke
    std::uint64_t index;       // 0, 1, 2, ... (cycles actually run)
  };
  using Body = std::function<void(const Cycle&)>;
  enum class Overrun {
    kSkip,       // wait for the first deadline still in the future (the grid stays)
    kRunAtOnce,  // start the next cycle at once; the grid restarts from the late cycle's end
  };

  // spec.period_ns must be > 0 (std::invalid_argument otherwise). The body is stored once here;
  // std::function never allocates when it is called.
  PeriodicTask(const ThreadSpec& spec, Body body);
  // Convenience for bodies that ignore the cycle information.
  template <class F>
  requires(std::invocable<F&> && !std::invocable<F&, const Cycle&>)
      PeriodicTask(const ThreadSpec& spec, F body)
      : PeriodicTask(spec, Body([fn = std::move(body)](const Cycle&) mutable { fn(); })) {}

  ~PeriodicTask() { stop(); }
  PeriodicTask(const PeriodicTask&) = delete;
  PeriodicTask& operator=(const PeriodicTask&) = delete;

  // Before start() (std::logic_error after): what a cycle that ends after its next deadline does.
  void set_overrun(Overrun policy);
  // Creates the thread (applying the spec) and starts the schedule. Once per task; a second call
  // throws std::logic_error.
  void start();
  // Any thread, including the body.
  void request_stop() noexcept;
  // From inside the body only: moves the next deadline by delta_ns (clamped to +-period/2), and
  // the grid with it (later deadlines keep the period from the moved one). A shift earlier
  // never moves the deadline before the body's end, so a shift alone never makes an overrun.
  // Used to phase-lock a task to its input (rt/phase_lock.hpp); counted in phase_shift_ns().
  void shift_next_deadline(std::int64_t delta_ns) noexcept;
  // request_stop() and join. Not from inside the body. Safe to call repeatedly or before start().
  void stop();

  [[nodiscard]] const ThreadSpec& spec() const noexcept { return spec_; }
  [[nodiscard]] std::int64_t period_ns() const noexcept { return spec_.period_ns; }
  // After start(): what apply_thread_spec achieved; before: all kNotRequested.
  [[nodiscard]] ThreadApplyStatus thread_status() const noexcept;

  // Statistics; any thread, any time.
  [[nodiscard]] std::uint64_t cycles() const noexcept { return cycles_.get(); }
  [[nodiscard]] std::uint64_t overruns() const noexcept { return overruns_.get(); }
  // When the first kOverrunTimes overruns ended (CLOCK_MONOTONIC, the body's end), so a caller
  // can tell a start-up overrun from one in steady state. Read after stop() (the task's thread
  // writes them without synchronisation; the join orders them before the read).
  static constexpr std::size_t kOverrunTimes = 64;
  [[nodiscard]] std::span<const std::int64_t> overrun_end_times_ns() const noexcept {
    const auto n = std::min<std::uint64_t>(overruns_.get(), kOverrunTimes);
    return {overrun_end_ns_.data(), static_cast<std::size_t>(n)};
  }
  [[nodiscard]] std::uint64_t missed_deadlines() const noexcept { return missed_deadlines_.get(); }
  // Sum of |shift| applied by shift_next_deadline (how much the grid moved).
  [[nodiscard]] std::uint64_t phase_shift_ns() const noexcept { return phase_shift_ns_.get(); }
  [[nodiscard]] const LatencyHistogram& wake_jitter() const noexcept { return wake_jitter_; }
  [[nodiscard]] const LatencyHistogram& cycle_time() const noexcept { return cycle_time_; }
  // Multi-line summary for the exit report (allocates; not for the real-time path).
  [[nodiscard]] std::string report() const;

 private:
  void run(std::stop_token stop) noexcept;

  ThreadSpec spec_;
  Body body_;
  Overrun overrun_ = Overrun::kSkip;
  std::atomic<bool> stop_flag_{false};  // request_stop() touches only this: safe from the body
  SingleWriterCounter cycles_;
  SingleWriterCounter overruns_;
  std::array<std::int64_t, kOverrunTimes> overrun_end_ns_{};  // the task's thread only
  SingleWriterCounter missed_deadlines_;
  SingleWriterCounter phase_shift_ns_;
  std::int64_t pending_shift_ns_ = 0;  // the task's thread only
  LatencyHistogram wake_jitter_;
  LatencyHistogram cycle_time_;
  std::optional<RtThread> thread_;  // last: destroyed (joined) first
};

}  // namespace vigs::rt
