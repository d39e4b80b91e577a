// bench_tracking: the tracking front end on the ICL-NUIM livingroom1 pair (frames 0 -> 2) at
// pixel stride 4 (and the tracker against its local map on two real 720x480 uHumans2 frames) —
// preprocessing (points, kNN, covariances) and GICP alignment, with 1 and 2 threads, from an
// IMU-quality initial guess (5 mm, 0.3 deg off) and from identity; plus our kd-tree against
// Debian's nanoflann. Accuracy is reported as counters (err_mm, err_deg).
//
// Extra flag (before the benchmark flags): --export_dir=DIR writes the stride-4 clouds and
// poses for an external comparison (small_gicp): DIR/source.bin and DIR/target.bin
// (uint32 n, then n x float32 xyz, camera frames, metres) and DIR/poses.txt (two lines,
// row-major 4x4: ground-truth T_2_0 and the IMU-quality guess).
#include <benchmark/benchmark.h>
#include <nanoflann.hpp>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "io/image_io.hpp"
#include "tracking/gicp.hpp"
#include "tracking/preprocess.hpp"
#include "tracking/settings_from_config.hpp"
#include "tracking/tracker.hpp"

namespace vigs::tracking {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
const std::string kIcl = std::string(VIGS_SHARED_DATA_DIR) + "/icl_nuim_livingroom1/";

struct Data {
  ImageF32 depth0, depth2;
  ImageU8 rgb0, rgb2;
  geometry::Pose T_2_0_true;
  geometry::Pose T_2_0_imu;  // truth perturbed by 5 mm and 0.3 deg
  PinholeCamera camera{640, 480, 525.0, 525.0, 319.5, 239.5};
};

geometry::Pose read_icl_pose(std::ifstream& in) {
  int a = 0, b = 0, c = 0;
  in >> a >> b >> c;
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int k = 0; k < 4; ++k) in >> m(r, k);
  }
  return geometry::Pose(m);
}

const Data& data() {
  static const Data d = [] {
    Data x;
    x.depth0 = io::read_depth_m(kIcl + "depth_00000.png", 0.001);
    x.depth2 = io::read_depth_m(kIcl + "depth_00002.png", 0.001);
    x.rgb0 = io::read_rgb(kIcl + "color_00000.jpg");
    x.rgb2 = io::read_rgb(kIcl + "color_00002.jpg");
    std::ifstream in(kIcl + "trajectory.log");
    const geometry::Pose T_w_0 = read_icl_pose(in);
    read_icl_pose(in);
    const geometry::Pose T_w_2 = read_icl_pose(in);
    x.T_2_0_true = T_w_2.inverse() * T_w_0;
    const geometry::Pose perturb =
        geometry::make_pose(Eigen::Vector3d(1.0, 1.0, -1.0).normalized() * 0.3 * kDeg,
                            Eigen::Vector3d(1.0, -2.0, 2.0).normalized() * 0.005);
    x.T_2_0_imu = perturb * x.T_2_0_true;
    return x;
  }();
  return d;
}

FramePreprocessor::Setting pre_setting(Regularization reg = Regularization::normalized_ellipse,
                                       KnnSearch knn = KnnSearch::image_grid) {
  FramePreprocessor::Setting s;
  s.depth.pixel_stride = 4;
  s.covariance.regularization = reg;
  s.covariance.knn_search = knn;
  return s;
}

void BM_DepthToPoints(benchmark::State& state) {
  const Data& d = data();
  DepthToPoints d2p(d.camera, pre_setting().depth);
  GaussianCloud cloud;
  for (auto _ : state) {
    d2p.convert(d.depth0, d.rgb0, cloud);
    benchmark::DoNotOptimize(cloud.points_m.data());
  }
  state.counters["points"] = static_cast<double>(cloud.size());
}
BENCHMARK(BM_DepthToPoints)->Unit(benchmark::kMillisecond);

// Points + covariances of one frame, as a GICP source (what the tracker does per frame):
// neighbours through the image (knn_kdtree:0, the default) or a kd-tree (1).
void BM_Preprocess(benchmark::State& state) {
  const Data& d = data();
  rt::WorkerTeam team(static_cast<int>(state.range(0)));
  const KnnSearch knn = state.range(1) == 0 ? KnnSearch::image_grid : KnnSearch::kd_tree;
  FramePreprocessor pre(d.camera, pre_setting(Regularization::normalized_ellipse, knn), team);
  GaussianCloud cloud;
  for (auto _ : state) {
    pre.process(d.depth0, d.rgb0, cloud);
    benchmark::DoNotOptimize(cloud.cov_m2.data());
  }
  state.counters["points"] = static_cast<double>(cloud.size());
  state.counters["knn_fallbacks"] = static_cast<double>(pre.last_knn_fallbacks());
}
BENCHMARK(BM_Preprocess)
    ->ArgNames({"threads", "knn_kdtree"})
    ->ArgsProduct({{1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same plus a kd-tree over the points, as for a GICP target (CloudTarget).
void BM_PreprocessTarget(benchmark::State& state) {
  const Data& d = data();
  rt::WorkerTeam team(static_cast<int>(state.range(0)));
  FramePreprocessor pre(d.camera, pre_setting(), team);
  GaussianCloud cloud;
  KdTree tree;
  for (auto _ : state) {
    pre.process(d.depth0, d.rgb0, cloud, tree);
    benchmark::DoNotOptimize(cloud.cov_m2.data());
  }
  state.counters["points"] = static_cast<double>(cloud.size());
}
BENCHMARK(BM_PreprocessTarget)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// kNN back ends on the covariance workload: build over the frame, then k = 10 for every point.
void BM_KnnOwnKdTree(benchmark::State& state) {
  const Data& d = data();
  GaussianCloud cloud;
  DepthToPoints(d.camera, pre_setting().depth).convert(d.depth0, d.rgb0, cloud);
  KdTree tree(KdTree::Setting{static_cast<int>(state.range(0))});
  std::uint32_t idx[10];
  float d2[10];
  for (auto _ : state) {
    tree.build(cloud.points_m);
    for (const std::uint32_t i : tree.leaf_order()) {
      benchmark::DoNotOptimize(tree.knn(cloud.points_m[i], 10, idx, d2));
    }
  }
}
BENCHMARK(BM_KnnOwnKdTree)
    ->ArgName("leaf")
    ->Arg(4)
    ->Arg(8)
    ->Arg(16)
    ->Arg(32)
    ->Unit(benchmark::kMillisecond);

// The image-grid search on the same workload (k = 10 for every point; no build step, the grid
// comes with the points). Uncertified points are counted, not searched.
void BM_KnnImageGrid(benchmark::State& state) {
  const Data& d = data();
  GaussianCloud cloud;
  PixelGrid grid;
  DepthToPoints(d.camera, pre_setting().depth).convert(d.depth0, d.rgb0, cloud, &grid);
  const OrganizedKnn knn;
  std::uint32_t idx[10];
  float d2[10];
  int uncertified = 0;
  for (auto _ : state) {
    uncertified = 0;
    for (std::uint32_t i = 0; i < cloud.size(); ++i) {
      uncertified += knn.knn(grid, cloud.points_m, i, 10, idx, d2) < 0 ? 1 : 0;
    }
  }
  state.counters["uncertified"] = uncertified;
}
BENCHMARK(BM_KnnImageGrid)->Unit(benchmark::kMillisecond);

void BM_KdTreeBuild(benchmark::State& state) {
  const Data& d = data();
  GaussianCloud cloud;
  DepthToPoints(d.camera, pre_setting().depth).convert(d.depth0, d.rgb0, cloud);
  KdTree tree;
  for (auto _ : state) {
    tree.build(cloud.points_m);
    benchmark::DoNotOptimize(tree.leaf_order().data());
  }
}
BENCHMARK(BM_KdTreeBuild)->Unit(benchmark::kMillisecond);

// The same in the frame's raster order, to show what the leaf-order traversal buys.
void BM_KnnOwnKdTreeRasterOrder(benchmark::State& state) {
  const Data& d = data();
  GaussianCloud cloud;
  DepthToPoints(d.camera, pre_setting().depth).convert(d.depth0, d.rgb0, cloud);
  KdTree tree;
  std::uint32_t idx[10];
  float d2[10];
  for (auto _ : state) {
    tree.build(cloud.points_m);
    for (const auto& p : cloud.points_m) benchmark::DoNotOptimize(tree.knn(p, 10, idx, d2));
  }
}
BENCHMARK(BM_KnnOwnKdTreeRasterOrder)->Unit(benchmark::kMillisecond);

struct NanoflannCloud {
  const std::vector<Eigen::Vector3f>* pts;
  [[nodiscard]] std::size_t kdtree_get_point_count() const { return pts->size(); }
  [[nodiscard]] float kdtree_get_pt(std::size_t i, std::size_t dim) const {
    return (*pts)[i][static_cast<Eigen::Index>(dim)];
  }
  template <class Bbox>
  bool kdtree_get_bbox(Bbox&) const {
    return false;
  }
};
using NanoflannTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, NanoflannCloud>,
                                        NanoflannCloud, 3, std::uint32_t>;

void BM_KnnNanoflann(benchmark::State& state) {
  const Data& d = data();
  GaussianCloud cloud;
  DepthToPoints(d.camera, pre_setting().depth).convert(d.depth0, d.rgb0, cloud);
  NanoflannCloud adaptor{&cloud.points_m};
  std::uint32_t idx[10];
  float d2[10];
  for (auto _ : state) {
    NanoflannTree tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    tree.buildIndex();
    for (const auto& p : cloud.points_m) {
      benchmark::DoNotOptimize(tree.knnSearch(p.data(), 10, idx, d2));
    }
  }
}
BENCHMARK(BM_KnnNanoflann)->Unit(benchmark::kMillisecond);

struct Prepared {
  GaussianCloud src, tgt;
  KdTree src_tree, tgt_tree;
  PixelGrid tgt_grid;
  /// The target as GICP sees it: through the image (grid) or, with kd_tree, the tree alone.
  [[nodiscard]] CloudTarget target(bool kd_tree) const {
    return CloudTarget{&tgt, &tgt_tree, kd_tree ? nullptr : &tgt_grid};
  }
};

void report(benchmark::State& state, const GicpResult& r) {
  const geometry::PoseError e = geometry::pose_error(data().T_2_0_true, r.T_t_s);
  state.counters["err_mm"] = e.translation_m * 1e3;
  state.counters["err_deg"] = e.rotation_rad / kDeg;
  state.counters["iterations"] = r.iterations;
  state.counters["converged"] = r.verdict == GicpVerdict::converged ? 1.0 : 0.0;
}

// Args: guess (0 identity, 1 IMU quality), threads, regularisation (0 ellipse, 1 plane),
// correspondences through the target's kd-tree only (1) or through its image (0, default).
void BM_Align(benchmark::State& state) {
  const Data& d = data();
  const int threads = static_cast<int>(state.range(1));
  const Regularization reg =
      state.range(2) == 0 ? Regularization::normalized_ellipse : Regularization::plane;
  rt::WorkerTeam team(threads);
  FramePreprocessor pre(d.camera, pre_setting(reg), team);
  Prepared p;
  pre.process(d.depth0, d.rgb0, p.src);
  pre.process(d.depth2, d.rgb2, p.tgt, p.tgt_tree, &p.tgt_grid);
  Gicp::Setting gs;
  gs.num_threads = threads;
  Gicp gicp(gs);
  const geometry::Pose init = state.range(0) == 0 ? geometry::Pose::Identity() : d.T_2_0_imu;
  GicpResult r;
  const bool kd_tree = state.range(3) != 0;
  for (auto _ : state) {
    r = gicp.align(p.target(kd_tree), p.src, init);
    benchmark::DoNotOptimize(r.T_t_s.data());
  }
  report(state, r);
}
BENCHMARK(BM_Align)
    ->ArgNames({"imu_guess", "threads", "plane_reg", "kdtree_target"})
    ->ArgsProduct({{0, 1}, {1, 2}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The whole tracking step for a new frame: source preprocessing + alignment against the
// prepared target (correspondences through its image, or its kd-tree only with arg 2 = 1).
void BM_TrackingStep(benchmark::State& state) {
  const Data& d = data();
  const int threads = static_cast<int>(state.range(1));
  rt::WorkerTeam team(threads);
  FramePreprocessor pre(d.camera, pre_setting(), team);
  Prepared p;
  pre.process(d.depth2, d.rgb2, p.tgt, p.tgt_tree, &p.tgt_grid);
  Gicp::Setting gs;
  gs.num_threads = threads;
  Gicp gicp(gs);
  const geometry::Pose init = state.range(0) == 0 ? geometry::Pose::Identity() : d.T_2_0_imu;
  const bool kd_tree = state.range(2) != 0;
  GicpResult r;
  for (auto _ : state) {
    pre.process(d.depth0, d.rgb0, p.src);
    r = gicp.align(p.target(kd_tree), p.src, init);
    benchmark::DoNotOptimize(r.T_t_s.data());
  }
  report(state, r);
}
BENCHMARK(BM_TrackingStep)
    ->ArgNames({"imu_guess", "threads", "kdtree_target"})
    ->ArgsProduct({{0, 1}, {1, 2}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The tracker's per-frame work in the pipeline: frame 0 against a local map holding frame 2
// (voxel-hash correspondences instead of a kd-tree), IMU-quality guess, config defaults.
void BM_TrackerFrameVsLocalMap(benchmark::State& state) {
  const Data& d = data();
  config::TrackingSettings cfg;
  cfg.gicp.num_threads = static_cast<int>(state.range(0));
  Tracker tracker(d.camera, tracker_setting(cfg));
  const geometry::Pose I = geometry::Pose::Identity();
  tracker.track(0, d.depth2, d.rgb2, &I);  // map anchored at frame 2 = world
  TrackingOutput out;
  std::int64_t t_ns = 0;
  for (auto _ : state) {
    t_ns += 33'333'333;
    out = tracker.track(t_ns, d.depth0, d.rgb0, &d.T_2_0_imu);
    benchmark::DoNotOptimize(out.T_w_c.data());
  }
  report(state, out.gicp);
  state.counters["tracked"] = out.status == TrackingStatus::tracked ? 1.0 : 0.0;
  state.counters["map_points"] = static_cast<double>(tracker.local_map().num_points());
}
BENCHMARK(BM_TrackerFrameVsLocalMap)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same per-frame work at the paper's resolution on real data: the two uHumans2 office frames
// in ../shared/data (720x480, float depth in metres, Kimera-VIO's test data). The local map holds
// frame 0 (= world), frame 1 is tracked against it from the identity (the frames carry no ground
// truth; the motion found is reported), config defaults otherwise.
void BM_TrackerFrameVsLocalMapUHumans720(benchmark::State& state) {
  static const std::string dir = std::string(VIGS_SHARED_DATA_DIR) + "/uhumans2_frames/";
  static const ImageF32 depth0 = io::read_depth_m(dir + "depth_img_0.tiff", 1.0);
  static const ImageF32 depth1 = io::read_depth_m(dir + "depth_img_1.tiff", 1.0);
  static const ImageU8 rgb0 = io::read_rgb(dir + "left_img_0.png");
  static const ImageU8 rgb1 = io::read_rgb(dir + "left_img_1.png");
  const PinholeCamera camera{720, 480, 415.69219381653056, 415.69219381653056, 360.0, 240.0};
  config::TrackingSettings cfg;
  cfg.gicp.num_threads = static_cast<int>(state.range(0));
  Tracker tracker(camera, tracker_setting(cfg));
  const geometry::Pose I = geometry::Pose::Identity();
  tracker.track(0, depth0, rgb0, &I);
  TrackingOutput out;
  std::int64_t t_ns = 0;
  for (auto _ : state) {
    t_ns += 50'000'000;  // 20 Hz
    out = tracker.track(t_ns, depth1, rgb1, &I);
    benchmark::DoNotOptimize(out.T_w_c.data());
  }
  const geometry::PoseError motion = geometry::pose_error(I, out.T_w_c);
  state.counters["motion_mm"] = motion.translation_m * 1e3;
  state.counters["motion_deg"] = motion.rotation_rad / kDeg;
  state.counters["iterations"] = out.gicp.iterations;
  state.counters["tracked"] = out.status == TrackingStatus::tracked ? 1.0 : 0.0;
  state.counters["map_points"] = static_cast<double>(tracker.local_map().num_points());
}
BENCHMARK(BM_TrackerFrameVsLocalMapUHumans720)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// Initial-guess modes compared on the five ICL-NUIM frames: the map is anchored at the true
// first pose; the IMU pose is the truth perturbed by 5 mm and 0.3 deg. Counters: mean GICP
// iterations per frame and the last frame's error.
void BM_TrackerSequenceByGuessMode(benchmark::State& state) {
  const Data& d = data();
  static const std::vector<std::pair<ImageF32, ImageU8>> frames = [] {
    std::vector<std::pair<ImageF32, ImageU8>> f;
    for (int i = 0; i < 5; ++i) {
      char name[16];
      std::snprintf(name, sizeof name, "%05d", i);
      f.emplace_back(io::read_depth_m(kIcl + "depth_" + name + ".png", 0.001),
                     io::read_rgb(kIcl + "color_" + name + ".jpg"));
    }
    return f;
  }();
  std::ifstream in(kIcl + "trajectory.log");
  std::vector<geometry::Pose> gt;
  for (int i = 0; i < 5; ++i) gt.push_back(read_icl_pose(in));
  const geometry::Pose perturb =
      geometry::make_pose(Eigen::Vector3d(1.0, 1.0, -1.0).normalized() * 0.3 * kDeg,
                          Eigen::Vector3d(1.0, -2.0, 2.0).normalized() * 0.005);
  config::TrackingSettings cfg;
  cfg.initial_guess = state.range(0) == 0   ? InitialGuessMode::imu
                      : state.range(0) == 1 ? InitialGuessMode::constant_velocity
                                            : InitialGuessMode::previous_pose;
  double iterations = 0.0;
  geometry::PoseError last;
  for (auto _ : state) {
    Tracker tracker(d.camera, tracker_setting(cfg));
    iterations = 0.0;
    for (int i = 0; i < 5; ++i) {
      const geometry::Pose imu = i == 0 ? gt[0] : gt[static_cast<std::size_t>(i)] * perturb;
      const TrackingOutput out =
          tracker.track(i * 33'333'333LL, frames[static_cast<std::size_t>(i)].first,
                        frames[static_cast<std::size_t>(i)].second, &imu);
      iterations += out.gicp.iterations / 4.0;
      last = geometry::pose_error(gt[static_cast<std::size_t>(i)], out.T_w_c);
    }
  }
  state.counters["mean_iterations"] = iterations;
  state.counters["last_err_mm"] = last.translation_m * 1e3;
  state.counters["last_err_deg"] = last.rotation_rad / kDeg;
  (void)d;
}
BENCHMARK(BM_TrackerSequenceByGuessMode)
    ->ArgName("mode_imu0_cv1_prev2")
    ->Arg(0)
    ->Arg(1)
    ->Arg(2)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void write_cloud(const std::string& path, const std::vector<Eigen::Vector3f>& pts) {
  std::ofstream out(path, std::ios::binary);
  const auto n = static_cast<std::uint32_t>(pts.size());
  out.write(reinterpret_cast<const char*>(&n), sizeof n);
  for (const auto& p : pts) out.write(reinterpret_cast<const char*>(p.data()), 3 * sizeof(float));
  if (!out) throw std::runtime_error("cannot write " + path + " (does the folder exist?)");
}

void export_clouds(const std::string& dir) {
  const Data& d = data();
  DepthToPoints d2p(d.camera, pre_setting().depth);
  GaussianCloud c0, c2;
  d2p.convert(d.depth0, d.rgb0, c0);
  d2p.convert(d.depth2, d.rgb2, c2);
  write_cloud(dir + "/source.bin", c0.points_m);
  write_cloud(dir + "/target.bin", c2.points_m);
  std::ofstream out(dir + "/poses.txt");
  out.precision(17);
  for (const geometry::Pose* T : {&d.T_2_0_true, &d.T_2_0_imu}) {
    for (int r = 0; r < 4; ++r) {
      for (int k = 0; k < 4; ++k) out << T->matrix()(r, k) << (r == 3 && k == 3 ? "\n" : " ");
    }
  }
  std::printf("exported %zu source and %zu target points to %s\n", c0.size(), c2.size(),
              dir.c_str());
}

}  // namespace
}  // namespace vigs::tracking

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--export_dir=", 13) == 0) {
      try {
        vigs::tracking::export_clouds(argv[i] + 13);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_tracking: %s\n", e.what());
        return 1;
      }
      for (int j = i; j + 1 < argc; ++j) argv[j] = argv[j + 1];
      --argc;
      --i;
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
