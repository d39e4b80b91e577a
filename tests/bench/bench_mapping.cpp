// Mapping benchmark: about 200k Gaussians inserted from ray-cast views of a synthetic room, with
// opacity 0.1 (fresh) or 0.5-1 (trained-like). Each measurement runs beside the single-threaded
// scalar reference of the same math (Reference/...), so the ratio is meaningful on a shared
// machine. The CPU column is process CPU time (all threads), the wall column real time.
// Counters: gaussians, visible tile pairs, bytes per Gaussian. BM_IterationLargeMap: an
// iteration on a map twenty rooms long, Adam dense against visible-only.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <random>

#include "mapping/map_optimizer.hpp"
#include "synthetic_room.hpp"

namespace {

using namespace vigs;

struct Scene {
  mapping::GaussianMap map;
  PinholeCamera k;
  bench::RoomView view;
  std::vector<float> rgb, depth;
};

/// opacity_mode 0: all 0.1; 1: uniform in [0.5, 1).
const Scene& scene(int width, int opacity_mode) {
  static std::map<std::pair<int, int>, std::unique_ptr<Scene>> cache;
  auto& slot = cache[{width, opacity_mode}];
  if (slot) return *slot;
  slot = std::make_unique<Scene>();
  Scene& s = *slot;
  const int height = width * 3 / 4;
  const double f = 0.8 * width;
  s.k = PinholeCamera{width, height, f, f, 0.5 * width - 0.5, 0.5 * height - 0.5};
  // the map is built at 640x480 regardless of the benchmark resolution
  static const mapping::GaussianMap base =
      bench::build_room_map(PinholeCamera{640, 480, 512.0, 512.0, 319.5, 239.5}, 24, 0.025, 2);
  s.map = base;
  if (opacity_mode == 1) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(0.5f, 0.999f);
    for (auto& v : s.map.opacity_logit) v = mapping::logit(u(rng));
  }
  s.view = bench::render_room(s.k, bench::room_pose(0.4, Eigen::Vector3d(0.1, 0.0, 0.2)));
  s.rgb.resize(s.view.rgb.data.size());
  for (std::size_t i = 0; i < s.rgb.size(); ++i) s.rgb[i] = s.view.rgb.data[i] / 255.0f;
  s.depth = s.view.depth_m.data;
  return s;
}

struct Config {
  bool reference;  // single thread, scalar kernel
};

std::unique_ptr<vigs::rt::WorkerTeam> make_pool(bool reference) {
  return reference ? nullptr : std::make_unique<vigs::rt::WorkerTeam>(2);
}

mapping::RasterSettings raster_settings(bool reference) {
  mapping::RasterSettings rs;
  rs.use_simd = !reference;
  return rs;
}

void set_counters(benchmark::State& state, const Scene& s, const mapping::Rasterizer<float>& r) {
  state.counters["gaussians"] = static_cast<double>(s.map.size());
  state.counters["tile_pairs"] = static_cast<double>(r.tile_pairs());
}

void BM_Forward(benchmark::State& state, bool reference) {
  const Scene& s = scene(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  auto pool = make_pool(reference);
  mapping::Rasterizer<float> ras(raster_settings(reference), pool.get());
  const auto cam = mapping::RenderCamera::from(s.k, s.view.T_w_c);
  mapping::RenderResult<float> out;
  for (auto _ : state) {
    ras.forward(s.map, cam, out);
    benchmark::DoNotOptimize(out.color.data());
  }
  set_counters(state, s, ras);
}

void BM_Backward(benchmark::State& state, bool reference) {
  const Scene& s = scene(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  auto pool = make_pool(reference);
  mapping::Rasterizer<float> ras(raster_settings(reference), pool.get());
  const auto cam = mapping::RenderCamera::from(s.k, s.view.T_w_c);
  mapping::RenderResult<float> out;
  ras.forward(s.map, cam, out);
  mapping::PhotometricLoss<float> loss;
  std::vector<float> vc(out.color.size()), vd(out.depth.size());
  loss.evaluate(out, s.rgb.data(), s.depth.data(), vc.data(), vd.data());
  mapping::GaussianMap grad;
  for (auto _ : state) {
    ras.backward(s.map, cam, out, vc.data(), vd.data(), nullptr, grad);
    benchmark::DoNotOptimize(grad.mean_w.data());
  }
  set_counters(state, s, ras);
}

/// The timed loop of the iteration benchmarks: optimiser iterations on the scene's view.
void iterate_on_scene_view(benchmark::State& state, mapping::MapOptimizer& opt,
                           mapping::GaussianMap& map, const Scene& s) {
  const mapping::TrainingView view{mapping::RenderCamera::from(s.k, s.view.T_w_c), s.rgb.data(),
                                   s.depth.data()};
  for (auto _ : state) {
    const auto terms = opt.iterate(map, view);
    benchmark::DoNotOptimize(terms.total);
  }
  state.counters["gaussians"] = static_cast<double>(map.size());
}

void BM_Iteration(benchmark::State& state, bool reference) {
  const Scene& s = scene(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  auto pool = make_pool(reference);
  config::MappingSettings ms;
  ms.prune_every = 1000000;  // measure the steady state, not pruning
  mapping::MapOptimizer opt(ms, pool.get());
  opt.rasterizer().settings() = raster_settings(reference);
  mapping::GaussianMap map = s.map;
  iterate_on_scene_view(state, opt, map, s);
  state.counters["bytes_per_gaussian"] = opt.bytes_per_gaussian(map);
}

/// The room map plus `copies` copies of it, each 30 m further along world x: a large map of
/// which the view sees one room (on the live office the camera sees a few hundred thousand of
/// four million Gaussians). Adam dense (every Gaussian, torch.optim.Adam) against visible-only,
/// and every Gaussian projected against block culling (map_blocks.hpp).
void BM_IterationLargeMap(benchmark::State& state) {
  const int copies = static_cast<int>(state.range(0));
  const bool visible_only = state.range(1) != 0;
  const bool blocks = state.range(2) != 0;
  const Scene& s = scene(640, 1);
  mapping::GaussianMap map = s.map;
  const std::size_t room = s.map.size();
  map.reserve(room * static_cast<std::size_t>(copies + 1));
  for (int c = 1; c <= copies; ++c)
    for (std::size_t i = 0; i < room; ++i) {
      const float mean[3] = {s.map.mean_w[3 * i] + 30.0f * static_cast<float>(c),
                             s.map.mean_w[3 * i + 1], s.map.mean_w[3 * i + 2]};
      map.push_back(mean, &s.map.log_scale[3 * i], &s.map.quat_wxyz[4 * i], s.map.opacity_logit[i],
                    &s.map.color_rgb[3 * i]);
    }
  auto pool = make_pool(false);
  config::MappingSettings ms;
  ms.prune_every = 1000000;
  ms.adam.visible_only = visible_only;
  mapping::MapOptimizer opt(ms, pool.get());
  opt.use_blocks(blocks);
  iterate_on_scene_view(state, opt, map, s);
  state.counters["culled_blocks"] = static_cast<double>(opt.rasterizer().culled_blocks());
  state.counters["visible"] = static_cast<double>(opt.rasterizer().visible_ids().size());
}

void args(benchmark::internal::Benchmark* b) {
  for (int w : {320, 640})
    for (int op : {0, 1}) b->Args({w, op});
  b->ArgNames({"width", "opaque"})
      ->Unit(benchmark::kMillisecond)
      ->MeasureProcessCPUTime()  // CPU column: all threads of the process
      ->UseRealTime();
}

BENCHMARK_CAPTURE(BM_Forward, Tiled2ThreadsSimd, false)->Apply(args);
BENCHMARK_CAPTURE(BM_Forward, Reference, true)->Apply(args);
BENCHMARK_CAPTURE(BM_Backward, Tiled2Threads, false)->Apply(args);
BENCHMARK_CAPTURE(BM_Backward, Reference, true)->Apply(args);
BENCHMARK_CAPTURE(BM_Iteration, Tiled2ThreadsSimd, false)->Apply(args);
BENCHMARK_CAPTURE(BM_Iteration, Reference, true)->Apply(args);
BENCHMARK(BM_IterationLargeMap)
    ->Args({0, 0, 0})
    ->Args({0, 1, 1})
    ->Args({19, 0, 0})
    ->Args({19, 1, 0})
    ->Args({19, 1, 1})
    ->ArgNames({"copies", "visible_only", "blocks"})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
