// WorkerTeam: a fixed team of threads for deterministic data-parallel loops, the one thread team
// of the tracker and the mapper (it replaced tracking::ForkJoin and mapping::WorkerPool).
//
// run(fn) calls fn(m) once for every member m in [0, size()) — m = 0 on the calling thread, the
// others on the team's worker threads — and returns when all are done. The caller partitions the
// work from m alone (chunk(), for_each_interleaved()) and sums partial results in member order,
// so a result is bit-identical run to run for the same team size. run_claimed(n, fn) instead
// hands items out to whichever member is free, for work whose per-item results do not depend on
// the member (the mapper's: its SCHED_IDLE threads are preempted at any moment). A run_claimed()
// job waits only for the workers that joined it: when the caller has claimed past the last item
// it closes the job, and a worker that wakes later (not yet scheduled, or preempted before it
// joined) finds it closed and leaves it alone (late_workers()). So a worker the scheduler holds
// back costs the caller nothing but its share, where run() must wait for it to start and finish.
//
// Threads: size() - 1 RtThreads started once in the constructor, each named and scheduled from
// the thread table. Worker m takes worker_spec(first_worker, m): member 1 is exactly the table
// entry (e.g. `tracker_w1`: the tracker's priority on the other CPU), further members are named
// `<prefix>_w<m>` with the same priority and no pinning (a 2-core target has no CPU for them).
//
// Hand-off without a mutex (the tracker calls run() about 30 times per frame): a generation
// counter announces a job, a pending counter reports completion, both 32-bit atomics that the
// waiting side may first spin on for spin_ns and then sleeps on with a futex (FUTEX_WAIT on the
// counter word itself, woken by FUTEX_WAKE only when someone is asleep).
// When to spin: only when every worker got SCHED_FIFO (the live pipeline's `tracker_w1`, pinned
// to the CPU the tracker does not use). Then the peer is certain to be running, and the gaps
// between GICP's parallel regions (a 6x6 solve, microseconds) are shorter than a futex
// sleep/wake round trip, so a short spin saves a wake-up per region. Under SCHED_OTHER (tools,
// tests, a process without CAP_SYS_NICE) a spinning thread burns the time slice its peer needs:
// bench_rt's BM_TeamRun measured an empty job at about 300 us with a 20 us spin against 7 us
// futex-only on this loaded 2-core machine. So the default (kSpinWhenRealtime) spins
// kRealtimeSpinNs when the workers are real-time and not at all otherwise.
// Why not std::atomic::wait: libstdc++'s spin length and sched_yield calls are not ours to set,
// and its notify bookkeeping lives in a process-wide table shared with every other atomic wait.
//
// run() neither allocates nor locks. An exception thrown by fn on any member is caught there;
// run() waits for every member, then rethrows the one from the lowest member index (the others
// are dropped). Capturing an exception may allocate; that is the failure path only.
// Not re-entrant: one run() at a time, from one owning thread.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <type_traits>
#include <vector>

#include "rt/cache_line.hpp"
#include "rt/rt_thread.hpp"
#include "rt/thread_table.hpp"

namespace vigs::rt {

// Worker m's spec for a team whose member 1 is `first_worker` (a table entry named `..._w1`):
// m == 1: `first_worker` itself; m > 1: name `..._w<m>`, same priority, cpu -1.
[[nodiscard]] ThreadSpec worker_spec(const ThreadSpec& first_worker, int member);

class WorkerTeam {
 public:
  static constexpr std::int64_t kSpinWhenRealtime = -1;  // spin_ns: decide from the workers
  static constexpr std::int64_t kRealtimeSpinNs = 20'000;
  static constexpr int kMaxSize = 64;

  // size is clamped to [1, kMaxSize]; a team of 1 starts no thread and run() calls fn(0).
  // The default spec names the workers `worker_w<m>` at normal priority (tools and tests);
  // the live pipeline passes the thread table's entry (rt::apply_policy'd).
  explicit WorkerTeam(int size = 1,
                      const ThreadSpec& first_worker = ThreadSpec{.name = "worker_w1"},
                      std::int64_t spin_ns = kSpinWhenRealtime);
  ~WorkerTeam();
  WorkerTeam(const WorkerTeam&) = delete;
  WorkerTeam& operator=(const WorkerTeam&) = delete;
  WorkerTeam(WorkerTeam&&) = delete;
  WorkerTeam& operator=(WorkerTeam&&) = delete;

  [[nodiscard]] int size() const noexcept { return size_; }
  // The spin before a futex sleep in effect (0: futex only).
  [[nodiscard]] std::int64_t spin_ns() const noexcept {
    return spin_ns_.load(std::memory_order_relaxed);
  }
  // The spec and apply status of worker m in [1, size()).
  [[nodiscard]] const RtThread& worker(int m) const {
    return *workers_[static_cast<std::size_t>(m - 1)];
  }

  // Calls fn(m) for every member m (fn(0) on this thread) and waits for all of them.
  template <class Fn>
  void run(Fn&& fn) {
    if (size_ == 1) {
      fn(0);
      return;
    }
    using F = std::remove_reference_t<Fn>;
    dispatch(const_cast<void*>(static_cast<const void*>(std::addressof(fn))),
             [](void* f, int m) { (*static_cast<F*>(f))(m); });
  }

  // Calls fn(m, i) once for every i in [0, n): items are claimed one at a time, in ascending
  // order, by whichever member is free (an atomic ticket), so the partition is not fixed.
  // For work whose result per item does not depend on the member that computed it (each item
  // writes its own outputs; members only own scratch): then a member the scheduler preempts
  // holds up the join by at most one item, where a fixed partition waits for its whole share.
  // The mapper's team needs this: its threads are SCHED_IDLE and the tracker's SCHED_FIFO
  // threads take either CPU at any moment. Sums over items stay fixed-order by writing per-item
  // partials and reducing them afterwards (rasterizer backward, SSIM). One claim per item: keep
  // items at tens of microseconds or more (chunk finer work).
  template <class Fn>
  void run_claimed(std::size_t n, Fn&& fn) {
    const auto claim_loop = [&](int m) {
      for (std::size_t i = claim_.fetch_add(1, std::memory_order_relaxed); i < n;
           i = claim_.fetch_add(1, std::memory_order_relaxed))
        fn(m, i);
    };
    claim_.store(0, std::memory_order_relaxed);  // published by dispatch()'s release of the job
    if (size_ == 1) {
      claim_loop(0);
      return;
    }
    using F = decltype(claim_loop);
    dispatch(
        const_cast<void*>(static_cast<const void*>(std::addressof(claim_loop))),
        [](void* f, int m) { (*static_cast<const F*>(f))(m); }, true);
  }

  // Calls fn(i) for member m's items of [0, n): blocks of `block` items dealt round robin (block
  // b goes to member b % members), so uneven work spreads evenly while the partition stays fixed.
  template <class Fn>
  static void for_each_interleaved(std::size_t n, int m, int members, std::size_t block, Fn&& fn) {
    const std::size_t step = block * static_cast<std::size_t>(members);
    for (std::size_t b = block * static_cast<std::size_t>(m); b < n; b += step) {
      const std::size_t e = b + block < n ? b + block : n;
      for (std::size_t i = b; i < e; ++i) fn(i);
    }
  }

  // [begin, end) of `n` items for member m: contiguous, fixed, near-equal chunks.
  static void chunk(std::size_t n, int m, int members, std::size_t& begin, std::size_t& end) {
    begin = n * static_cast<std::size_t>(m) / static_cast<std::size_t>(members);
    end = n * static_cast<std::size_t>(m + 1) / static_cast<std::size_t>(members);
  }

  // Statistics (any thread): jobs dispatched, and how often a waiting side had to sleep on the
  // futex after its spin ran out (workers waiting for a job, the caller waiting for the team).
  [[nodiscard]] std::uint64_t jobs() const noexcept {
    return jobs_.load(std::memory_order_relaxed);
  }
  [[nodiscard]] std::uint64_t worker_sleeps() const noexcept {
    return worker_sleeps_.load(std::memory_order_relaxed);
  }
  [[nodiscard]] std::uint64_t caller_sleeps() const noexcept {
    return caller_sleeps_.load(std::memory_order_relaxed);
  }
  // Workers that woke for a run_claimed() job the caller had already closed (all items claimed).
  [[nodiscard]] std::uint64_t late_workers() const noexcept {
    return late_workers_.load(std::memory_order_relaxed);
  }

 private:
  using Call = void (*)(void*, int);
  // claimed: a run_claimed() job (workers join while it is open, the caller waits for those that
  // joined); otherwise every member runs it and the caller waits for all.
  void dispatch(void* task, Call call, bool claimed = false);
  // A worker joins the open run_claimed() job: false when it is closed.
  bool join_claimed() noexcept;
  // The generation word: a job counter times 2, plus 1 for a run_claimed() job.
  static constexpr std::uint32_t kClaimedJob = 1;
  // admit_: kOpen while the caller may still be claiming items, plus the workers inside the job.
  static constexpr std::uint32_t kOpen = 1u << 31;
  void worker_loop(int m) noexcept;
  void stop_team() noexcept;  // stop flag, wake every worker, join

  int size_ = 1;
  std::atomic<std::int64_t> spin_ns_{0};
  // Written by the caller before the generation bump (release), read by workers after (acquire).
  void* task_ = nullptr;
  Call call_ = nullptr;
  std::vector<std::exception_ptr> errors_;  // per member, sized once; written on failure only
  alignas(kCacheLineSize) std::atomic<std::uint32_t> generation_{0};
  std::atomic<std::uint32_t> sleeping_workers_{0};
  alignas(kCacheLineSize) std::atomic<std::uint32_t> pending_{0};
  std::atomic<std::uint32_t> caller_sleeping_{0};
  alignas(kCacheLineSize) std::atomic<std::size_t> claim_{0};    // run_claimed's next item
  alignas(kCacheLineSize) std::atomic<std::uint32_t> admit_{0};  // run_claimed: kOpen | joined
  alignas(kCacheLineSize) std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> jobs_{0};
  std::atomic<std::uint64_t> worker_sleeps_{0};
  std::atomic<std::uint64_t> caller_sleeps_{0};
  std::atomic<std::uint64_t> late_workers_{0};
  std::vector<std::unique_ptr<RtThread>> workers_;  // last: destroyed (joined) first
};

}  // namespace vigs::rt
