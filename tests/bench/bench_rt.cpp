// bench_rt: the real-time primitives against the obvious baseline, measured in the same run.
//
//  BM_Throughput<Ring|MutexQueue>  producer on CPU 0 pushes uint64 items to a consumer on CPU 1
//                                  as fast as it can; items_per_second.
//  BM_RoundTrip<Ring|MutexQueue>   ping-pong over two queues (CPU 0 <-> CPU 1); the time per
//                                  iteration is one round trip.
//  BM_TeamRun<Team>/items/gap_us  one 2-member parallel region per iteration: each member sums
//                                  its half of `items` floats (0 = an empty job: the hand-off
//                                  alone), with `gap_us` of caller-only work before each region
//                                  (0: back to back like GICP's iterations; 200: the workers have
//                                  gone to sleep). Team = rt::WorkerTeam with its real-time spin
//                                  (20 us, then futex), WorkerTeamNoSpin (futex only), and the two
//                                  teams it replaced (tests/bench/legacy_teams.hpp): ForkJoin
//                                  (atomic wait/notify) and WorkerPool (mutex + condition
//                                  variables).
// Baseline: std::deque under a std::mutex, bounded to the same capacity, polled in a spin loop
// (no condition variable), so both sides do the same work apart from the synchronisation.
// Target (BENCHMARKS.md): ring throughput >= 5x the mutex queue's.
// Run: build/bin/bench_rt --benchmark_format=json
#include <benchmark/benchmark.h>
#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "legacy_teams.hpp"
#include "rt/clock.hpp"
#include "rt/latency_histogram.hpp"
#include "rt/overwrite_ring.hpp"
#include "rt/spsc_ring.hpp"
#include "rt/thread_table.hpp"
#include "rt/worker_team.hpp"

namespace {

using vigs::rt::SpscRing;

constexpr std::size_t kCapacity = 1024;
constexpr int kProducerCpu = 0;
constexpr int kConsumerCpu = 1;

template <class T>
class MutexQueue {
 public:
  explicit MutexQueue(std::size_t capacity) : capacity_(capacity) {}
  bool try_push(const T& v) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (queue_.size() >= capacity_) return false;
    queue_.push_back(v);
    return true;
  }
  bool try_pop(T& out) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (queue_.empty()) return false;
    out = queue_.front();
    queue_.pop_front();
    return true;
  }

 private:
  std::mutex mutex_;
  std::deque<T> queue_;
  std::size_t capacity_;
};

// Pins the calling (benchmark) thread to one CPU for the scope and restores its mask afterwards.
class ScopedPin {
 public:
  explicit ScopedPin(int cpu) {
    saved_ok_ = pthread_getaffinity_np(pthread_self(), sizeof saved_, &saved_) == 0;
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(static_cast<std::size_t>(cpu), &set);
    pinned_ = pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0;
  }
  ~ScopedPin() {
    if (saved_ok_) pthread_setaffinity_np(pthread_self(), sizeof saved_, &saved_);
  }
  ScopedPin(const ScopedPin&) = delete;
  ScopedPin& operator=(const ScopedPin&) = delete;
  bool pinned() const { return pinned_; }

 private:
  cpu_set_t saved_{};
  bool saved_ok_ = false;
  bool pinned_ = false;
};

void pin_helper_thread(const char* name, int cpu) {
  (void)vigs::rt::apply_thread_spec(
      vigs::rt::ThreadSpec{.name = name, .sched_fifo_priority = 0, .cpu = cpu});
}

template <class Queue>
void BM_Throughput(benchmark::State& state) {
  Queue queue(kCapacity);
  const auto n = static_cast<std::uint64_t>(state.max_iterations);
  std::atomic<bool> order_ok{true};
  std::thread consumer([&] {
    pin_helper_thread("bench_consumer", kConsumerCpu);
    for (std::uint64_t i = 0; i < n; ++i) {
      std::uint64_t v = 0;
      while (!queue.try_pop(v)) {
      }
      if (v != i) order_ok.store(false, std::memory_order_relaxed);
    }
  });
  ScopedPin pin(kProducerCpu);
  std::uint64_t i = 0;
  for (auto _ : state) {
    while (!queue.try_push(i)) {
    }
    ++i;
  }
  consumer.join();
  if (!order_ok.load()) state.SkipWithError("items arrived out of order");
  if (!pin.pinned()) state.SetLabel("not pinned");
  state.SetItemsProcessed(state.iterations());
}

template <class Queue>
void BM_RoundTrip(benchmark::State& state) {
  Queue ping(kCapacity);
  Queue pong(kCapacity);
  const auto n = static_cast<std::uint64_t>(state.max_iterations);
  std::thread echo([&] {
    pin_helper_thread("bench_echo", kConsumerCpu);
    for (std::uint64_t i = 0; i < n; ++i) {
      std::uint64_t v = 0;
      while (!ping.try_pop(v)) {
      }
      while (!pong.try_push(v)) {
      }
    }
  });
  ScopedPin pin(kProducerCpu);
  std::uint64_t i = 0;
  for (auto _ : state) {
    while (!ping.try_push(i)) {
    }
    std::uint64_t back = 0;
    while (!pong.try_pop(back)) {
    }
    benchmark::DoNotOptimize(back);
    ++i;
  }
  echo.join();
  if (!pin.pinned()) state.SetLabel("not pinned");
  state.SetItemsProcessed(state.iterations());
}

using Ring = SpscRing<std::uint64_t>;
using Locked = MutexQueue<std::uint64_t>;

BENCHMARK_TEMPLATE(BM_Throughput, Ring)->UseRealTime();
BENCHMARK_TEMPLATE(BM_Throughput, Locked)->UseRealTime();
BENCHMARK_TEMPLATE(BM_RoundTrip, Ring)->UseRealTime();
BENCHMARK_TEMPLATE(BM_RoundTrip, Locked)->UseRealTime();

// Single-thread costs of the other hot-path calls.
void BM_MonotonicNs(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(vigs::rt::monotonic_ns());
}
BENCHMARK(BM_MonotonicNs);

void BM_HistogramRecord(benchmark::State& state) {
  auto h = std::make_unique<vigs::rt::LatencyHistogram>();
  std::int64_t v = 1;
  for (auto _ : state) {
    h->record(v);
    v = (v * 1103515245 + 12345) & ((std::int64_t{1} << 30) - 1);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_HistogramRecord);

void BM_OverwriteRingPushPop(benchmark::State& state) {
  struct Pose {
    std::int64_t t_ns;
    double p[3];
    double q[4];
  };
  vigs::rt::OverwriteRing<Pose> ring(8);
  Pose pose{};
  for (auto _ : state) {
    pose.t_ns += 1;
    ring.push(pose);
    Pose out;
    benchmark::DoNotOptimize(ring.try_pop(out));
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_OverwriteRingPushPop);

struct WorkerTeamSpin {
  vigs::rt::WorkerTeam team{2, vigs::rt::ThreadSpec{.name = "bench_w1"},
                            vigs::rt::WorkerTeam::kRealtimeSpinNs};
  template <class F>
  void run(F&& f) {
    team.run(f);
  }
};
struct WorkerTeamNoSpin {
  vigs::rt::WorkerTeam team{2, vigs::rt::ThreadSpec{.name = "bench_w1"}, 0};
  template <class F>
  void run(F&& f) {
    team.run(f);
  }
};
struct ForkJoin {
  vigs::bench_legacy::ForkJoin team{2};
  template <class F>
  void run(F&& f) {
    team.run(f);
  }
};
struct WorkerPool {
  vigs::bench_legacy::WorkerPool team{2};
  template <class F>
  void run(F&& f) {
    team.run(f);  // converts to std::function, as mapping's callers did
  }
};

template <class Team>
void BM_TeamRun(benchmark::State& state) {
  const auto items = static_cast<std::size_t>(state.range(0));
  const std::int64_t gap_ns = state.range(1) * 1000;
  std::vector<float> data(items, 1.0f);
  double partial[2 * 8] = {};
  Team team;
  for (auto _ : state) {
    if (gap_ns > 0) {
      const std::int64_t until = vigs::rt::monotonic_ns() + gap_ns;
      while (vigs::rt::monotonic_ns() < until) {
      }
    }
    team.run([&](int m) {
      std::size_t b = 0, e = 0;
      vigs::rt::WorkerTeam::chunk(items, m, 2, b, e);
      double s = 0;
      for (std::size_t i = b; i < e; ++i) s += data[i];
      partial[m * 8] = s;
    });
    benchmark::DoNotOptimize(partial[0] + partial[8]);
  }
  state.SetItemsProcessed(state.iterations());
}

#define VIGS_TEAM_BENCH(T)          \
  BENCHMARK_TEMPLATE(BM_TeamRun, T) \
      ->Args({0, 0})                \
      ->Args({20000, 0})            \
      ->Args({20000, 200})          \
      ->UseRealTime()
VIGS_TEAM_BENCH(WorkerTeamSpin);
VIGS_TEAM_BENCH(WorkerTeamNoSpin);
VIGS_TEAM_BENCH(ForkJoin);
VIGS_TEAM_BENCH(WorkerPool);

}  // namespace

BENCHMARK_MAIN();
