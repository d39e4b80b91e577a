// Mapping benchmark: about 200k Gaussians inserted from ray-cast views of a synthetic room, with
// opacity 0.1 (fresh) or 0.5-1 (trained-like). Each measurement runs beside the single-threaded
// scalar reference of the same math (Reference/...), so the ratio is meaningful on a shared
// machine. The CPU column is process CPU time (all threads), the wall column real time.
// Counters: gaussians, visible tile pairs, bytes per Gaussian. BM_IterationLargeMap: an
// iteration on a map twenty rooms long, Adam dense against visible-only. BM_OfficeMap: the
// simulated office at 720x480 as the live mapper inserts it (keyframes at stride 4, the
// footprint rule, the insertion gate), rendered from a view between keyframes, with the
// kernels' out-of-reach skip on and off (the same render, bit for bit), and the AVX-512 kernels
// (an 8 x 2 pixel block per vector, when the CPU has them) against the AVX2 ones (8 pixels of a
// row); BM_OfficeMapHalfRes: the same view at half resolution. BM_Ssim720 and BM_Loss720: SSIM
// and the whole loss at 720x480, AVX-512 filters against AVX2, the team against one thread.
// BM_SelectiveAdamStep: visible-only Adam on 300 k Gaussians that skipped 3 steps (their
// moments decayed first) against the same step with nothing skipped.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <random>

#include "core/config/robot_config.hpp"
#include "mapping/half_res_view.hpp"
#include "mapping/insertion.hpp"
#include "mapping/insertion_gate.hpp"
#include "mapping/loss.hpp"
#include "mapping/map_optimizer.hpp"
#include "mapping/rgbd_keyframe.hpp"
#include "mapping/ssim.hpp"
#include "sim/simulator.hpp"
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

/// The office at 720x480, no people: keyframes every 0.3 s from 1 s to 6 s inserted at stride 4
/// with the footprint rule behind the insertion gate (as mapper.cpp does, without the far
/// field), and the recorded view at 4.15 s (between two keyframes) to render and train on.
struct OfficeScene {
  mapping::GaussianMap map;
  PinholeCamera k;
  Eigen::Isometry3d T_w_c;
  std::vector<float> rgb, depth;
};

const OfficeScene& office_scene() {
  static const OfficeScene scene = [] {
    OfficeScene s;
    config::RobotConfig cfg;
    cfg.sim.preset = "office";
    cfg.sim.humans = 0;
    cfg.sim.seconds = 7.0;
    sim::Simulator simulator(cfg);
    s.k = PinholeCamera::from_settings(cfg.camera);
    mapping::GaussianInserter inserter(mapping::InsertSettings{});
    mapping::Rasterizer<float> gate_ras;
    mapping::RenderResult<float> gate_render;
    std::vector<char> keep;
    sim::RgbdFrame f;
    for (int i = 0; i <= 16; ++i) {
      const double t = 1.0 + 0.3 * i;
      simulator.render_at(t, 1, f);
      ImageU8 rgb(f.width, f.height, 3);
      rgb.data = f.color;
      ImageF32 depth(f.width, f.height, 1);
      depth.data = f.depth_m;
      const Eigen::Isometry3d T_w_c = simulator.camera_pose(t);
      mapping::KeyframeGaussians kf = mapping::keyframe_from_rgbd(s.k, rgb, depth, T_w_c);
      const auto cam = mapping::RenderCamera::from(s.k, T_w_c);
      if (s.map.size() > 0) {
        gate_ras.forward(s.map, cam, gate_render);
        mapping::gate_points(kf, cam, gate_render, mapping::GateSettings{}, keep);
        inserter.insert(s.map, kf, &keep);
      } else {
        inserter.insert(s.map, kf);
      }
    }
    simulator.render_at(4.15, 2, f);
    s.T_w_c = simulator.camera_pose(4.15);
    s.rgb.resize(f.color.size());
    for (std::size_t i = 0; i < s.rgb.size(); ++i) s.rgb[i] = f.color[i] / 255.0f;
    s.depth = f.depth_m;
    return s;
  }();
  return scene;
}

/// range(0): 0 forward, 1 forward + backward (the rasterizer alone), 2 a whole optimiser
/// iteration; range(1): the kernels' out-of-reach skip (1, the default) or not (0, baseline).
void BM_OfficeMap(benchmark::State& state) {
  const OfficeScene& s = office_scene();
  const int what = static_cast<int>(state.range(0));
  vigs::rt::WorkerTeam pool(2);
  mapping::RasterSettings rs;
  rs.skip_out_of_reach = state.range(1) != 0;
  rs.use_avx512 = state.range(2) != 0;
  const auto cam = mapping::RenderCamera::from(s.k, s.T_w_c);
  if (what == 2) {
    config::MappingSettings ms;
    ms.prune_every = 1000000;
    mapping::MapOptimizer opt(ms, &pool);
    opt.rasterizer().settings() = rs;
    opt.loss().use_avx512(rs.use_avx512);  // SSIM's filters follow the kernels' width
    mapping::GaussianMap map = s.map;
    const mapping::TrainingView view{cam, s.rgb.data(), s.depth.data()};
    for (auto _ : state) benchmark::DoNotOptimize(opt.iterate(map, view).total);
    state.counters["tile_pairs"] = static_cast<double>(opt.rasterizer().tile_pairs());
  } else {
    mapping::Rasterizer<float> ras(rs, &pool);
    mapping::RenderResult<float> out;
    ras.forward(s.map, cam, out);
    std::vector<float> vc(out.color.size()), vd(out.depth.size());
    for (std::size_t i = 0; i < vc.size(); ++i) vc[i] = out.color[i] - s.rgb[i];
    for (std::size_t i = 0; i < vd.size(); ++i) vd[i] = s.depth[i] > 0 ? 0.1f : 0.0f;
    mapping::GaussianMap grad;
    for (auto _ : state) {
      ras.forward(s.map, cam, out);
      if (what == 1) ras.backward(s.map, cam, out, vc.data(), vd.data(), nullptr, grad);
      benchmark::DoNotOptimize(out.color.data());
    }
    state.counters["tile_pairs"] = static_cast<double>(ras.tile_pairs());
  }
  state.counters["gaussians"] = static_cast<double>(s.map.size());
}

/// The same office view one pyramid level down (360x240, mapping.coarse_iterations: most of the
/// live mapper's iterations): range(0) 1 forward + backward, 2 a whole iteration; range(1) the
/// AVX-512 kernels (1) or the AVX2 ones (0).
void BM_OfficeMapHalfRes(benchmark::State& state) {
  const OfficeScene& s = office_scene();
  vigs::rt::WorkerTeam pool(2);
  mapping::RasterSettings rs;
  rs.use_avx512 = state.range(1) != 0;
  mapping::HalfResView half;
  mapping::make_half_res_view(mapping::RenderCamera::from(s.k, s.T_w_c), s.rgb.data(),
                              s.depth.data(), half);
  if (state.range(0) == 2) {
    config::MappingSettings ms;
    ms.prune_every = 1000000;
    mapping::MapOptimizer opt(ms, &pool);
    opt.rasterizer().settings() = rs;
    opt.loss().use_avx512(rs.use_avx512);
    mapping::GaussianMap map = s.map;
    const mapping::TrainingView view{half.camera, half.rgb.data(), half.depth_m.data()};
    for (auto _ : state) benchmark::DoNotOptimize(opt.iterate(map, view).total);
  } else {
    mapping::Rasterizer<float> ras(rs, &pool);
    mapping::RenderResult<float> out;
    ras.forward(s.map, half.camera, out);
    std::vector<float> vc(out.color.size()), vd(out.depth.size());
    for (std::size_t i = 0; i < vc.size(); ++i) vc[i] = out.color[i] - half.rgb[i];
    for (std::size_t i = 0; i < vd.size(); ++i) vd[i] = half.depth_m[i] > 0 ? 0.1f : 0.0f;
    mapping::GaussianMap grad;
    for (auto _ : state) {
      ras.forward(s.map, half.camera, out);
      ras.backward(s.map, half.camera, out, vc.data(), vd.data(), nullptr, grad);
      benchmark::DoNotOptimize(out.color.data());
    }
  }
  state.counters["gaussians"] = static_cast<double>(s.map.size());
}

/// SSIM and its gradient (the loss's) on the office view at 720x480 against a shifted copy:
/// range(0) the row filters in AVX-512 (2), AVX2 (1) or the plain loop (0).
/// One selective Adam step on 300 k of a 1.2 M-Gaussian map, one thread: every fourth
/// Gaussian. rotate = 1: the four such sets in turn, so each Gaussian has skipped 3 steps when
/// its set comes again and its moments are decayed first; rotate = 0 (the baseline): the same
/// set every step, nothing to decay, the same memory pattern.
void BM_SelectiveAdamStep(benchmark::State& state) {
  constexpr std::size_t kSets = 4, kSeen = 300'000;
  const bool rotate = state.range(0) != 0;
  vigs::mapping::GaussianMap map;
  map.resize(kSeen * kSets);
  std::vector<std::vector<int>> ids(kSets);
  for (std::size_t i = 0; i < map.size(); ++i) ids[i % kSets].push_back(static_cast<int>(i));
  vigs::mapping::Adam adam;
  const auto one_range = [](std::size_t n, auto&& f) { f(std::size_t{0}, n); };
  const auto grad_of = [](std::size_t k, float* g) {
    for (std::size_t j = 0; j < 14; ++j) g[j] = 1e-3f * static_cast<float>((k + j) % 7) - 3e-3f;
  };
  for (std::size_t s = 0; s < 2 * kSets; ++s)  // every Gaussian has moments
    adam.step_selected(map, ids[s % kSets], grad_of, one_range);
  std::size_t step = 0;
  for (auto _ : state) {
    adam.step_selected(map, ids[rotate ? step++ % kSets : 0], grad_of, one_range);
    benchmark::DoNotOptimize(map.color_rgb.data());
  }
  state.counters["ns_per_gaussian"] = benchmark::Counter(
      static_cast<double>(kSeen) * static_cast<double>(state.iterations()) * 1e-9,
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_Ssim720(benchmark::State& state) {
  const OfficeScene& s = office_scene();
  vigs::rt::WorkerTeam pool(2);
  mapping::SsimOptions o;
  o.use_simd = state.range(0) != 0;
  o.use_avx512 = state.range(0) == 2;
  mapping::Ssim<float> ssim(o, &pool);
  std::vector<float> x(s.rgb.size()), grad(s.rgb.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = s.rgb[(i + 3 * 721) % x.size()];
  for (auto _ : state)
    benchmark::DoNotOptimize(ssim.evaluate(x.data(), s.rgb.data(), s.k.width_px, s.k.height_px, 3,
                                           nullptr, grad.data()));
}

/// The whole training loss with its gradients (masks, L1 colour and depth, SSIM) on the office
/// view at 720x480 against a shifted render: range(0) threads (1: every pass on the caller, the
/// baseline; 2: the mapper's team), range(1) SSIM's filters in AVX-512 (1) or AVX2 (0).
void BM_Loss720(benchmark::State& state) {
  const OfficeScene& s = office_scene();
  std::unique_ptr<vigs::rt::WorkerTeam> pool;
  if (state.range(0) > 1) pool = std::make_unique<vigs::rt::WorkerTeam>(2);
  mapping::PhotometricLoss<float> loss(mapping::LossSettings{}, pool.get(), true);
  loss.use_avx512(state.range(1) != 0);
  mapping::RenderResult<float> r;
  r.width = s.k.width_px;
  r.height = s.k.height_px;
  r.color.resize(s.rgb.size());
  for (std::size_t i = 0; i < r.color.size(); ++i)
    r.color[i] = s.rgb[(i + 3 * 721) % r.color.size()];
  r.depth.resize(s.depth.size());
  for (std::size_t i = 0; i < r.depth.size(); ++i)
    r.depth[i] = 1.02f * s.depth[(i + 721) % r.depth.size()];
  std::vector<float> vc(r.color.size()), vd(r.depth.size());
  for (auto _ : state)
    benchmark::DoNotOptimize(
        loss.evaluate(r, s.rgb.data(), s.depth.data(), vc.data(), vd.data()).total);
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

BENCHMARK(BM_OfficeMap)
    ->ArgsProduct({{0, 1, 2}, {1, 0}, {1, 0}})
    ->ArgNames({"pass", "skip", "avx512"})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

BENCHMARK(BM_OfficeMapHalfRes)
    ->ArgsProduct({{1, 2}, {1, 0}})
    ->ArgNames({"pass", "avx512"})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

BENCHMARK(BM_SelectiveAdamStep)
    ->ArgName("rotate")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK(BM_Ssim720)
    ->ArgName("simd")
    ->Arg(2)
    ->Arg(1)
    ->Arg(0)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_Loss720)
    ->ArgsProduct({{2, 1}, {1, 0}})
    ->ArgNames({"threads", "avx512"})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
