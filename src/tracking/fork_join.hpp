#pragma once
// A fixed team of threads for deterministic data-parallel loops. run(fn) calls fn(t) once for
// every team member t in [0, size()) — t = 0 on the calling thread — and returns when all are
// done. Work is partitioned by the caller from t alone (fixed partition), and partial results
// are summed by the caller in team order, so results are bit-identical run to run.
// Workers are started once; run() neither allocates nor takes a lock (C++20 atomic
// wait/notify). Not re-entrant: one run() at a time, from one owning thread.
#include <atomic>
#include <cstdint>
#include <functional>
#include <thread>
#include <vector>

namespace vigs::tracking {

class ForkJoin {
 public:
  explicit ForkJoin(int num_threads = 1);
  ~ForkJoin();
  ForkJoin(const ForkJoin&) = delete;
  ForkJoin& operator=(const ForkJoin&) = delete;

  [[nodiscard]] int size() const { return num_threads_; }

  /// fn is called as fn(int thread_index); it must not throw.
  template <class Fn>
  void run(Fn&& fn) {
    if (num_threads_ == 1) {
      fn(0);
      return;
    }
    task_ = &fn;
    call_ = [](void* f, int t) { (*static_cast<std::remove_reference_t<Fn>*>(f))(t); };
    dispatch();
  }

  /// Calls fn(i) for team member t's items of [0, n): blocks of `block` items dealt round
  /// robin (block b goes to member b % num_threads), so uneven work spreads evenly while the
  /// partition stays fixed.
  template <class Fn>
  static void for_each_interleaved(std::size_t n, int t, int num_threads, std::size_t block,
                                   Fn&& fn) {
    const std::size_t step = block * static_cast<std::size_t>(num_threads);
    for (std::size_t b = block * static_cast<std::size_t>(t); b < n; b += step) {
      const std::size_t e = b + block < n ? b + block : n;
      for (std::size_t i = b; i < e; ++i) fn(i);
    }
  }

  /// [begin, end) of `n` items for team member t: contiguous, fixed, near-equal chunks.
  static void chunk(std::size_t n, int t, int num_threads, std::size_t& begin, std::size_t& end) {
    begin = n * static_cast<std::size_t>(t) / static_cast<std::size_t>(num_threads);
    end = n * static_cast<std::size_t>(t + 1) / static_cast<std::size_t>(num_threads);
  }

 private:
  void dispatch();
  void worker(int t);

  int num_threads_ = 1;
  void* task_ = nullptr;
  void (*call_)(void*, int) = nullptr;
  std::atomic<std::uint32_t> generation_{0};
  std::atomic<int> pending_{0};
  std::atomic<bool> stop_{false};
  std::vector<std::thread> threads_;
};

}  // namespace vigs::tracking
