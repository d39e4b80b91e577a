#include "rt/periodic_task.hpp"

#include <sys/prctl.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "rt/clock.hpp"

namespace vigs::rt {

PeriodicTask::PeriodicTask(const ThreadSpec& spec, Body body)
    : spec_(spec), body_(std::move(body)) {
  if (spec_.period_ns <= 0) {
    throw std::invalid_argument("PeriodicTask '" + std::string(spec_.name.view()) +
                                "' needs period_ns > 0");
  }
  if (!body_) throw std::invalid_argument("PeriodicTask needs a body");
}

void PeriodicTask::set_overrun(Overrun policy) {
  if (thread_) throw std::logic_error("PeriodicTask::set_overrun() after start()");
  overrun_ = policy;
}

void PeriodicTask::start() {
  if (thread_) throw std::logic_error("PeriodicTask::start() called twice");
  thread_.emplace(spec_, [this](std::stop_token stop) { run(std::move(stop)); });
}

void PeriodicTask::request_stop() noexcept {
  stop_flag_.store(true, std::memory_order_release);
}

void PeriodicTask::shift_next_deadline(std::int64_t delta_ns) noexcept {
  const std::int64_t half = spec_.period_ns / 2;
  pending_shift_ns_ = delta_ns < -half ? -half : (delta_ns > half ? half : delta_ns);
}

void PeriodicTask::stop() {
  request_stop();
  if (thread_) thread_->join();
}

ThreadApplyStatus PeriodicTask::thread_status() const noexcept {
  return thread_ ? thread_->status() : ThreadApplyStatus{};
}

void PeriodicTask::run(std::stop_token stop) noexcept {
  // A SCHED_OTHER thread's timer wake-ups may be deferred by its timer slack (50 us by default)
  // to batch them; a periodic task wants its deadline. (SCHED_FIFO threads have no slack.)
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  const std::int64_t period = spec_.period_ns;
  std::int64_t deadline = monotonic_ns() + period;
  std::uint64_t index = 0;
  auto stopping = [&] {
    return stop_flag_.load(std::memory_order_acquire) || stop.stop_requested();
  };
  while (!stopping()) {
    sleep_until_ns(deadline);
    const std::int64_t wake = monotonic_ns();
    wake_jitter_.record(wake - deadline);
    if (stopping()) break;

    body_(Cycle{deadline, wake, index++});

    const std::int64_t end = monotonic_ns();
    cycle_time_.record(end - wake);
    cycles_.add();
    deadline += period;
    if (pending_shift_ns_ != 0) {
      // Earlier, but not before the body's end: a shift is not an overrun.
      const std::int64_t shifted = std::max(deadline + pending_shift_ns_, std::min(deadline, end));
      phase_shift_ns_.add(
          static_cast<std::uint64_t>(shifted > deadline ? shifted - deadline : deadline - shifted));
      deadline = shifted;
      pending_shift_ns_ = 0;
    }
    if (end > deadline) {
      if (overruns_.get() < kOverrunTimes) overrun_end_ns_[overruns_.get()] = end;
      overruns_.add();
      if (overrun_ == Overrun::kRunAtOnce) {
        deadline = end;  // the next cycle now, the grid from here
      } else {
        // Finished after the next deadline: skip to the first deadline still in the future.
        const std::int64_t skipped = (end - deadline) / period + 1;
        missed_deadlines_.add(static_cast<std::uint64_t>(skipped));
        deadline += skipped * period;
      }
    }
  }
}

std::string PeriodicTask::report() const {
  char head[160];
  std::snprintf(head, sizeof head, "%s: period=%s cycles=%llu overruns=%llu missed_deadlines=%llu",
                spec_.name.c_str(), format_duration_ns(spec_.period_ns).c_str(),
                static_cast<unsigned long long>(cycles()),
                static_cast<unsigned long long>(overruns()),
                static_cast<unsigned long long>(missed_deadlines()));
  return std::string(head) + "\n  " + wake_jitter_.report("wake jitter") + "\n  " +
         cycle_time_.report("cycle time");
}

}  // namespace vigs::rt
