#include "rt/worker_team.hpp"

#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <climits>
#include <string>

#include "rt/clock.hpp"

namespace vigs::rt {
namespace {

static_assert(sizeof(std::atomic<std::uint32_t>) == sizeof(std::uint32_t) &&
                  std::atomic<std::uint32_t>::is_always_lock_free,
              "the futex word is the atomic's own storage");

std::uint32_t* futex_word(std::atomic<std::uint32_t>& a) noexcept {
  return reinterpret_cast<std::uint32_t*>(&a);
}

// Sleeps while *word == expected (the kernel checks atomically); returns on a wake, a changed
// value (EAGAIN) or a signal (EINTR). Callers re-check their condition in a loop.
void futex_wait(std::atomic<std::uint32_t>& word, std::uint32_t expected) noexcept {
  (void)syscall(SYS_futex, futex_word(word), FUTEX_WAIT_PRIVATE, expected, nullptr, nullptr, 0);
}

void futex_wake(std::atomic<std::uint32_t>& word, int count) noexcept {
  (void)syscall(SYS_futex, futex_word(word), FUTEX_WAKE_PRIVATE, count, nullptr, nullptr, 0);
}

inline void cpu_relax() noexcept {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__)
  asm volatile("yield" ::: "memory");
#endif
}

// Spins until pred() or spin_ns elapsed; true when pred() held. The clock is read every 64
// polls (a vDSO call, no syscall).
template <class Pred>
bool spin_until(Pred pred, std::int64_t spin_ns) noexcept {
  if (spin_ns <= 0) return pred();
  const std::int64_t end_ns = monotonic_ns() + spin_ns;
  for (;;) {
    for (int i = 0; i < 64; ++i) {
      if (pred()) return true;
      cpu_relax();
    }
    if (monotonic_ns() >= end_ns) return pred();
  }
}

void bump(std::atomic<std::uint64_t>& c) noexcept {
  c.fetch_add(1, std::memory_order_relaxed);
}

}  // namespace

ThreadSpec worker_spec(const ThreadSpec& first_worker, int member) {
  if (member <= 1) return first_worker;
  std::string_view base = first_worker.name.view();
  while (!base.empty() && base.back() >= '0' && base.back() <= '9') base.remove_suffix(1);
  ThreadSpec s = first_worker;
  s.name = ThreadName(std::string(base) + std::to_string(member));
  s.cpu = -1;
  s.period_ns = 0;
  return s;
}

WorkerTeam::WorkerTeam(int size, const ThreadSpec& first_worker, std::int64_t spin_ns)
    : size_(std::clamp(size, 1, kMaxSize)), errors_(static_cast<std::size_t>(size_)) {
  // Workers start with `seen` = 0: no job can be announced before the constructor returns.
  try {
    workers_.reserve(static_cast<std::size_t>(size_ - 1));
    for (int m = 1; m < size_; ++m) {
      workers_.push_back(
          std::make_unique<RtThread>(worker_spec(first_worker, m), [this, m] { worker_loop(m); }));
    }
  } catch (...) {  // thread creation failed: stop the workers already running, then report
    stop_team();
    throw;
  }
  bool all_realtime = size_ > 1;
  for (const auto& w : workers_) {
    all_realtime = all_realtime && w->spec().sched_fifo_priority > 0 &&
                   w->status().scheduling == ApplyResult::kApplied;
  }
  // Atomic: the workers are already waiting (their first wait may still see 0).
  spin_ns_.store(spin_ns >= 0 ? spin_ns : (all_realtime ? kRealtimeSpinNs : 0),
                 std::memory_order_relaxed);
}

WorkerTeam::~WorkerTeam() {
  stop_team();
}

void WorkerTeam::stop_team() noexcept {
  stop_.store(true, std::memory_order_seq_cst);
  generation_.fetch_add(2, std::memory_order_seq_cst);
  futex_wake(generation_, INT_MAX);
  workers_.clear();  // joins
}

void WorkerTeam::dispatch(void* task, Call call, bool claimed) {
  task_ = task;
  call_ = call;
  if (claimed) {
    // Nobody is inside: the last job waited for them. Release: a worker still on its way from an
    // earlier claimed job may join this one through admit_ alone, without reading the
    // generation below, and must see task_, call_ and claim_ as they are now.
    admit_.store(kOpen, std::memory_order_release);
  } else {
    pending_.store(static_cast<std::uint32_t>(size_ - 1), std::memory_order_relaxed);
  }
  // The owning thread is the only writer of the generation (a job counter times 2, the low bit
  // the job's kind). seq_cst pairs with the workers' sleeping_workers_ increment before
  // FUTEX_WAIT: either we see a sleeper and wake it, or its FUTEX_WAIT sees the new generation
  // and returns at once. Also publishes task_, call_ and admit_ or pending_.
  const std::uint32_t next = ((generation_.load(std::memory_order_relaxed) >> 1) + 1) << 1;
  generation_.store(next | (claimed ? kClaimedJob : 0u), std::memory_order_seq_cst);
  bump(jobs_);
  if (sleeping_workers_.load(std::memory_order_seq_cst) != 0) futex_wake(generation_, INT_MAX);

  try {
    call(task, 0);
  } catch (...) {
    errors_[0] = std::current_exception();
  }

  // Wait on `word` until it reads 0: spin first, then sleep on the futex (the last worker to
  // leave wakes the caller when caller_sleeping_ is set).
  const auto wait_for_zero = [this](std::atomic<std::uint32_t>& word) {
    const auto done = [&word] { return word.load(std::memory_order_acquire) == 0; };
    if (spin_until(done, spin_ns_.load(std::memory_order_relaxed))) return;
    caller_sleeping_.store(1, std::memory_order_seq_cst);
    for (;;) {
      const std::uint32_t left = word.load(std::memory_order_seq_cst);
      if (left == 0) break;
      futex_wait(word, left);
    }
    caller_sleeping_.store(0, std::memory_order_relaxed);
    bump(caller_sleeps_);
  };
  if (claimed) {
    // Every item is claimed once the caller's own loop has returned: close the job to workers
    // that have not joined yet, then wait for those inside.
    if (admit_.fetch_and(~kOpen, std::memory_order_acq_rel) != kOpen) wait_for_zero(admit_);
  } else {
    wait_for_zero(pending_);
  }

  for (std::exception_ptr& e : errors_) {
    if (e) {
      std::exception_ptr first = std::move(e);
      for (std::exception_ptr& rest : errors_) rest = nullptr;
      std::rethrow_exception(first);
    }
  }
}

void WorkerTeam::worker_loop(int m) noexcept {
  std::uint32_t seen = 0;
  for (;;) {
    std::uint32_t g = seen;
    const auto announced = [&] {
      g = generation_.load(std::memory_order_acquire);
      return g != seen;
    };
    if (!spin_until(announced, spin_ns_.load(std::memory_order_relaxed))) {
      while (g == seen) {
        sleeping_workers_.fetch_add(1, std::memory_order_seq_cst);
        futex_wait(generation_, seen);
        sleeping_workers_.fetch_sub(1, std::memory_order_relaxed);
        g = generation_.load(std::memory_order_acquire);
      }
      bump(worker_sleeps_);
    }
    seen = g;
    if (stop_.load(std::memory_order_acquire)) return;
    // A run() job counts down pending_; a claimed job counts its members out of admit_.
    std::atomic<std::uint32_t>* done = &pending_;
    if ((g & kClaimedJob) != 0) {
      // A job that was announced while this worker slept or was held back may be closed by now
      // (or it may be a later claimed job; joining that one is as good): task_ is read only
      // from inside an open job, which the caller does not leave before everyone inside has.
      if (!join_claimed()) {
        bump(late_workers_);
        continue;
      }
      done = &admit_;
    }
    try {
      call_(task_, m);
    } catch (...) {
      errors_[static_cast<std::size_t>(m)] = std::current_exception();
    }
    // 1 before: this was the last member (of a claimed job: the last inside, after it closed).
    // It wakes the caller if it went to sleep (seq_cst: see dispatch).
    if (done->fetch_sub(1, std::memory_order_seq_cst) == 1 &&
        caller_sleeping_.load(std::memory_order_seq_cst) != 0) {
      futex_wake(*done, 1);
    }
  }
}

bool WorkerTeam::join_claimed() noexcept {
  std::uint32_t w = admit_.load(std::memory_order_acquire);
  while ((w & kOpen) != 0) {
    if (admit_.compare_exchange_weak(w, w + 1, std::memory_order_acq_rel,
                                     std::memory_order_acquire))
      return true;
  }
  return false;
}

}  // namespace vigs::rt
