// Simulator speed: one 720x480 RGB-D frame of the office with 1 and 2 ray-casting threads
// (24 people; and 0 or 60 people with 2 threads), the static BVH build, and one frame's MCAP
// encoding (16UC1 depth, zstd level 1). The default sequence runs in real time when a frame (render
// + write) takes < 50 ms of wall time; the requirement is <= 2x real time, i.e. < 100 ms.
#include <benchmark/benchmark.h>

#include <unistd.h>
#include <cstdio>
#include <string>

#include "sim/floor_plan.hpp"
#include "sim/mcap_sink.hpp"
#include "sim/simulator.hpp"

namespace {

vigs::config::RobotConfig office(int threads, int humans = 24) {
  vigs::config::RobotConfig cfg;
  cfg.sim.humans = humans;
  cfg.sim.render_threads = threads;
  return cfg;
}

void BM_RenderFrame(benchmark::State& state) {
  const vigs::sim::Simulator sim(
      office(static_cast<int>(state.range(0)), static_cast<int>(state.range(1))));
  vigs::sim::RgbdFrame f;
  std::uint64_t i = 0;
  for (auto _ : state) {
    // Walk along the route so that views vary (corridors, junctions, people).
    sim.render_at(5.0 + 0.5 * static_cast<double>(i % 200), i, f);
    benchmark::DoNotOptimize(f.depth_m.data());
    ++i;
  }
  state.counters["rays_per_s"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * 720.0 * 480.0, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderFrame)
    ->Args({1, 24})
    ->Args({2, 24})
    ->Args({2, 0})
    ->Args({2, 60})
    ->ArgNames({"threads", "humans"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(3.0);

void BM_BuildOfficeAndBvh(benchmark::State& state) {
  for (auto _ : state) {
    const vigs::sim::Simulator sim(office(1));
    benchmark::DoNotOptimize(sim.renderer().bvh().nodes().data());
  }
}
BENCHMARK(BM_BuildOfficeAndBvh)->Unit(benchmark::kMillisecond);

void BM_WriteFrameToMcap(benchmark::State& state) {
  const vigs::sim::Simulator sim(office(2));
  vigs::sim::RgbdFrame f;
  sim.render_at(10.0, 0, f);
  const std::string path = "/tmp/bench_sim_" + std::to_string(getpid()) + ".mcap";
  {
    vigs::sim::McapSink sink(path, {});
    std::int64_t t = 0;
    for (auto _ : state) {
      sink.frame(t, sim.camera(), f);
      t += 50'000'000;
    }
    sink.close();
  }
  std::remove(path.c_str());
}
BENCHMARK(BM_WriteFrameToMcap)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
