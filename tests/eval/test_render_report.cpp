// `vigs eval run` on a real RESULTS_DIR: a short simulated recording (apartment, reduced image
// size), a Gaussian map built from its RGB-D keyframes at the ground-truth camera poses with the
// mapping library, the ground-truth trajectory and a perturbed one. The map rendered at the true
// poses must match the recording clearly better than at the perturbed poses.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../common/scaled_camera.hpp"
#include "core/config/robot_config.hpp"
#include "eval/report.hpp"
#include "eval/trajectory_file.hpp"
#include "io/atomic_file.hpp"
#include "io/image_io.hpp"
#include "io/recording/recording_writer.hpp"
#include "io/tum_trajectory.hpp"
#include "mapping/insertion.hpp"
#include "mapping/map_optimizer.hpp"
#include "mapping/ply_io.hpp"
#include "mapping/rasterizer.hpp"
#include "mapping/rgbd_keyframe.hpp"
#include "sim/mcap_sink.hpp"
#include "sim/simulator.hpp"

namespace vigs::eval {
namespace {
namespace fs = std::filesystem;

std::string read_all(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

constexpr int kKeyframeEvery = 4;

/// Records the frames next to the MCAP file.
struct FrameTee : sim::SimSink {
  sim::SimSink* mcap = nullptr;
  std::vector<std::int64_t> t_ns;
  std::vector<sim::RgbdFrame> frames;
  PinholeCamera camera;
  void frame(std::int64_t t, const PinholeCamera& c, const sim::RgbdFrame& f) override {
    mcap->frame(t, c, f);
    t_ns.push_back(t);
    frames.push_back(f);
    camera = c;
  }
  void imu(const ImuSample& s) override { mcap->imu(s); }
  void ground_truth(std::int64_t t, const geometry::Pose& T) override { mcap->ground_truth(t, T); }
};

class RenderReportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::path(::testing::TempDir()) / ("vigs_render_report_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    const auto t0 = std::chrono::steady_clock::now();
    config::RobotConfig cfg;
    cfg.sim.preset = "apartment";
    cfg.sim.humans = 0;
    cfg.sim.seconds = 2.0;
    // A third of the default resolution: the same field of view at a ninth of the cost.
    vigs::test::use_default_camera_divided(cfg.camera, 3);
    sim::Simulator sim(cfg);
    T_b_c_ = sim.T_b_c();
    mcap_ = (dir_ / "seq.mcap").string();
    FrameTee tee;
    {
      sim::McapSink sink(mcap_, {});
      tee.mcap = &sink;
      sim.run(tee);
      sink.close();
    }
    frames_ = tee.frames.size();

    // The "run": keyframes every 4th frame, a map from their RGB-D at the true poses.
    const PinholeCamera& k = tee.camera;
    mapping::GaussianMap map;
    mapping::GaussianInserter inserter;
    mapping::RgbdSampling sampling;
    sampling.stride_px = 2;
    struct View {
      std::vector<float> rgb;
      std::vector<float> depth;
      mapping::TrainingView view;
    };
    std::vector<View> views;
    std::vector<io::TumPose> truth, perturbed;
    for (std::size_t i = 0; i < tee.frames.size(); ++i) {
      const double t = static_cast<double>(tee.t_ns[i]) * 1e-9;
      const geometry::Pose T_w_c = sim.camera_pose(t);
      io::TumPose p;
      p.t_s = t;
      p.p_w_m = T_w_c.translation();
      p.q_w = Eigen::Quaterniond(T_w_c.linear());
      truth.push_back(p);
      // 4 cm sideways and 2 degrees of yaw (about the camera's y axis).
      const geometry::Pose T_bad =
          T_w_c * geometry::make_pose(Eigen::Vector3d(0.04, 0.0, 0.0),
                                      Eigen::Quaterniond(Eigen::AngleAxisd(
                                          2.0 * M_PI / 180.0, Eigen::Vector3d::UnitY())));
      p.p_w_m = T_bad.translation();
      p.q_w = Eigen::Quaterniond(T_bad.linear());
      perturbed.push_back(p);
      if (i % kKeyframeEvery != 0) continue;
      keyframes_.push_back(t);
      const sim::RgbdFrame& f = tee.frames[i];
      ImageU8 rgb(f.width, f.height, 3);
      rgb.data = f.color;
      ImageF32 depth(f.width, f.height, 1);
      depth.data = f.depth_m;
      inserter.insert(map, mapping::keyframe_from_rgbd(k, rgb, depth, T_w_c, sampling));
      View v;
      v.rgb.assign(f.color.begin(), f.color.end());
      for (auto& c : v.rgb) c /= 255.0f;
      v.depth = f.depth_m;
      views.push_back(std::move(v));
      views.back().view = {mapping::RenderCamera::from(k, T_w_c), views.back().rgb.data(),
                           views.back().depth.data()};
    }
    config::MappingSettings ms;
    ms.threads = 2;
    vigs::rt::WorkerTeam pool(ms.threads);
    mapping::MapOptimizer opt(ms, &pool);
    for (int it = 0; it < 100; ++it)
      opt.iterate(map, views[static_cast<std::size_t>(it) % views.size()].view);
    gaussians_ = map.size();
    camera_ = k;
    mapping::write_gaussian_ply((dir_ / pipeline::kMapFile).string(), map);
    io::write_tum_trajectory((dir_ / pipeline::kTrajectoryFile).string(), truth);
    io::write_tum_trajectory((dir_ / "trajectory_perturbed.tum").string(), perturbed);
    write_text((dir_ / pipeline::kKeyframesFile).string(),
               pipeline::format_keyframe_times(keyframes_));
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    write_text((dir_ / pipeline::kStatsFile).string(),
               "{\"producer\": \"test_eval_render_report\", \"frames\": " +
                   std::to_string(frames_) + ", \"wall_s\": " + std::to_string(wall_s) +
                   ", \"peak_rss_bytes\": " + std::to_string(ru.ru_maxrss * 1024L) +
                   ", \"gaussians\": " + std::to_string(gaussians_) + "}\n");
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static ReportOptions options(const fs::path& dir, const std::string& estimate) {
    ReportOptions opt;
    opt.results_dir = dir.string();
    opt.gt_path = mcap_;
    opt.estimate_name = estimate;
    opt.T_b_c = T_b_c_;
    opt.ate.align = Alignment::kNone;
    opt.plots = false;
    opt.quality.threads = 2;
    return opt;
  }

  static inline fs::path dir_;
  static inline std::string mcap_;
  static inline std::size_t frames_ = 0, gaussians_ = 0;
  static inline std::vector<double> keyframes_;
  static inline geometry::Pose T_b_c_ = geometry::Pose::Identity();
  static inline PinholeCamera camera_;
};

TEST_F(RenderReportTest, TruePosesRenderClearlyBetterThanPerturbedOnes) {
  ASSERT_EQ(frames_, 41u);  // 2 s at 20 Hz
  const ReportResult good = write_report(options(dir_, pipeline::kTrajectoryFile));
  const std::string md = read_all(good.report_path);
  const ReportResult bad = write_report(options(dir_, "trajectory_perturbed.tum"));
  ASSERT_TRUE(good.quality_measured && bad.quality_measured);
  EXPECT_LT(good.ate.stats.max, 1e-6);  // the estimate is the ground truth
  EXPECT_NEAR(bad.ate.stats.rmse, 0.04, 1e-6);
  EXPECT_EQ(good.gaussians, static_cast<long>(gaussians_));
  EXPECT_GT(gaussians_, 1000u);

  // Every 5th of 41 frames: 0, 5, ..., 40. Held-out: the 30 non-keyframes, every 5th of them.
  EXPECT_EQ(good.quality.recorded_frames, 41u);
  EXPECT_EQ(good.quality.keyframe_frames, 11u);
  EXPECT_EQ(good.quality.every_nth.frames(), 9u);
  EXPECT_EQ(good.quality.held_out.frames(), 6u);
  for (const double t : good.quality.held_out.t_s)
    for (const double kf : keyframes_) EXPECT_GT(std::abs(t - kf), 0.01) << t;

  const double g = good.quality.every_nth.mean_psnr_db(), b = bad.quality.every_nth.mean_psnr_db();
  std::cout << "PSNR every 5th: true " << g << " dB, perturbed " << b << " dB; held-out true "
            << good.quality.held_out.mean_psnr_db() << " dB; SSIM true "
            << good.quality.every_nth.mean_ssim() << ", perturbed "
            << bad.quality.every_nth.mean_ssim() << "\n";
  EXPECT_GT(g, 16.0);  // the corridor beyond the 10 m depth range is not in the map
  EXPECT_GT(g, b + 3.0);
  EXPECT_GT(good.quality.held_out.mean_psnr_db(), bad.quality.held_out.mean_psnr_db() + 3.0);
  EXPECT_GT(good.quality.every_nth.mean_ssim(), bad.quality.every_nth.mean_ssim() + 0.05);
  EXPECT_GT(good.quality.every_nth.mean_ssim(), 0.5);
  // Over pixels with valid depth (the corridor beyond 10 m excluded) the map matches better.
  ASSERT_EQ(good.quality.every_nth.frames_with_depth(), 9u);
  std::cout << "valid depth: PSNR " << good.quality.every_nth.mean_psnr_valid_depth_db()
            << " dB, SSIM " << good.quality.every_nth.mean_ssim_valid_depth() << "\n";
  EXPECT_GT(good.quality.every_nth.mean_psnr_valid_depth_db(), g + 1.0);
  EXPECT_GT(good.quality.every_nth.mean_psnr_valid_depth_db(),
            bad.quality.every_nth.mean_psnr_valid_depth_db() + 3.0);
  EXPECT_LE(good.quality.every_nth.mean_ssim(), 1.0);

  // The JSON summary lists the held-out frames one by one, in the set's order.
  const auto j = nlohmann::json::parse(report_json(good, options(dir_, pipeline::kTrajectoryFile)));
  const auto& per_frame = j.at("quality").at("held_out").at("per_frame");
  ASSERT_EQ(per_frame.at("psnr_db").size(), 6u);
  ASSERT_EQ(per_frame.at("t_s").size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_NEAR(per_frame["t_s"][i].get<double>(), good.quality.held_out.t_s[i], 1e-3);
    EXPECT_NEAR(per_frame["psnr_db"][i].get<double>(), good.quality.held_out.psnr_db[i], 1e-3);
    EXPECT_NEAR(per_frame["ssim"][i].get<double>(), good.quality.held_out.ssim[i], 1e-4);
  }
  // and their PSNR over valid depth (every frame here has depth), whose mean is the set's
  ASSERT_EQ(per_frame.at("psnr_valid_depth_db").size(), 6u);
  double valid_sum = 0;
  for (std::size_t i = 0; i < 6; ++i)
    valid_sum += per_frame["psnr_valid_depth_db"][i].get<double>();
  EXPECT_NEAR(valid_sum / 6, good.quality.held_out.mean_psnr_valid_depth_db(), 1e-3);

  // The report states the numbers it measured.
  EXPECT_NE(md.find("## Rendering quality (PSNR, SSIM)"), std::string::npos) << md;
  char row[96];
  std::snprintf(row, sizeof row, "| every 5th frame | 9 | %.2f |", g);
  EXPECT_NE(md.find(row), std::string::npos) << md;
  EXPECT_NE(md.find("| held-out (never keyframes) | 6 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| Gaussians in the map | " + std::to_string(gaussians_) + " | map.ply |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| frames processed | 41 | stats.json |"), std::string::npos) << md;
  EXPECT_NE(md.find("stats.json frames / wall_s"), std::string::npos) << md;
  EXPECT_EQ(md.find("| peak memory (RSS) [MiB] | not measured"), std::string::npos) << md;
  EXPECT_NE(md.find("LPIPS"), std::string::npos);
  EXPECT_EQ(md.find("**PSNR and SSIM**"), std::string::npos) << md;

  // Rendered | recorded, three rows.
  ASSERT_EQ(good.quality.side_by_side_t_s.size(), 3u);
  const ImageU8 sbs = io::read_image_u8(good.quality.side_by_side_png);
  EXPECT_EQ(sbs.width, 2 * 240);
  EXPECT_EQ(sbs.height, 3 * 160);
  EXPECT_EQ(sbs.channels, 3);
  EXPECT_NE(md.find("![rendered vs recorded](plots/rendered_vs_recorded.png)"), std::string::npos);
}

// A run with the loop closer: trajectory.tum is corrected and the map follows it
// (map_loop_correction.hpp); trajectory_odometry.tum keeps the poses as tracked. The views are
// rendered at the estimate evaluated, so the corrected trajectory's render matches the map.
TEST_F(RenderReportTest, ALoopCorrectedRunIsRenderedAtItsCorrectedPoses) {
  const fs::path d = dir_ / "loop_corrected";
  fs::create_directories(d);
  for (const char* f : {pipeline::kMapFile, pipeline::kKeyframesFile, pipeline::kStatsFile})
    fs::copy_file(dir_ / f, d / f);
  fs::copy_file(dir_ / pipeline::kTrajectoryFile, d / pipeline::kTrajectoryFile);
  fs::copy_file(dir_ / "trajectory_perturbed.tum", d / pipeline::kOdometryTrajectoryFile);
  const ReportResult loop = write_report(options(d, pipeline::kTrajectoryFile));
  const ReportResult truth = write_report(options(dir_, pipeline::kTrajectoryFile));
  ASSERT_TRUE(loop.quality_measured && truth.quality_measured);
  EXPECT_LT(loop.ate.stats.max, 1e-6);  // the corrected trajectory's
  EXPECT_DOUBLE_EQ(loop.quality.every_nth.mean_psnr_db(), truth.quality.every_nth.mean_psnr_db());
  // Asked for the odometry by name, the views follow it.
  const ReportResult odometry = write_report(options(d, pipeline::kOdometryTrajectoryFile));
  EXPECT_NEAR(odometry.ate.stats.rmse, 0.04, 1e-6);
  EXPECT_LT(odometry.quality.every_nth.mean_psnr_db(),
            truth.quality.every_nth.mean_psnr_db() - 3.0);
}

TEST_F(RenderReportTest, MissingOptionalFilesAreReportedNotInvented) {
  const fs::path d = dir_ / "partial";
  fs::create_directories(d);
  fs::copy_file(dir_ / pipeline::kTrajectoryFile, d / pipeline::kTrajectoryFile);
  ReportResult r = write_report(options(d, pipeline::kTrajectoryFile));
  std::string md = read_all(r.report_path);
  EXPECT_FALSE(r.quality_measured);
  EXPECT_EQ(r.gaussians, -1);
  EXPECT_EQ(r.missing.size(), 3u);
  EXPECT_NE(md.find("**PSNR and SSIM** (every 5th frame and held-out frames) and the **rendered "
                    "views beside the recording**: the results hold no map.ply."),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| Gaussians in the map | not measured | map.ply |"), std::string::npos);
  EXPECT_NE(md.find("**Frames per second**: the results hold no stats.json."), std::string::npos);
  EXPECT_NE(md.find("**Peak memory**: the results hold no stats.json."), std::string::npos);
  EXPECT_EQ(md.find("## Rendering quality"), std::string::npos);

  // A map but no keyframes.txt: every 5th frame measured, held-out stated as not measured.
  fs::copy_file(dir_ / pipeline::kMapFile, d / pipeline::kMapFile);
  write_text((d / pipeline::kStatsFile).string(), "{\"fps\": 12.5}");
  r = write_report(options(d, pipeline::kTrajectoryFile));
  md = read_all(r.report_path);
  ASSERT_TRUE(r.quality_measured);
  EXPECT_EQ(r.quality.every_nth.frames(), 9u);
  EXPECT_EQ(r.quality.held_out.frames(), 0u);
  EXPECT_NE(md.find("**PSNR and SSIM on held-out frames**: no keyframes.txt"), std::string::npos)
      << md;
  EXPECT_NE(md.find("| frames per second | 12.50 | stats.json fps |"), std::string::npos) << md;
  EXPECT_NE(md.find("**Peak memory**: stats.json has no peak_rss_bytes."), std::string::npos);

  // Damaged stats.json: a clear error naming the file.
  write_text((d / pipeline::kStatsFile).string(), "{\"fps\": fast}");
  try {
    write_report(options(d, pipeline::kTrajectoryFile));
    FAIL();
  } catch (const pipeline::ResultsFileError& e) {
    EXPECT_NE(std::string(e.what()).find("stats.json: byte 8"), std::string::npos) << e.what();
  }
}

/// The map rendered at T_w_c as measure_render_quality renders it, rounded to 8 bits.
std::vector<std::uint8_t> render_u8(const mapping::GaussianMap& map, const PinholeCamera& camera,
                                    const geometry::Pose& T_w_c) {
  mapping::Rasterizer<float> ras(mapping::RasterSettings{});
  mapping::RenderResult<float> r;
  ras.forward(map, mapping::RenderCamera::from(camera, T_w_c), r);
  std::vector<std::uint8_t> out(r.color.size());
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = static_cast<std::uint8_t>(std::lround(255.0f * std::clamp(r.color[i], 0.0f, 1.0f)));
  return out;
}

// The map leaves walking people out by design. A recording whose static pixels are the map's
// own render (each channel off by exactly 2 grey levels: PSNR 20 log10(255 / 2) = 42.11 dB)
// and whose "person" pixels are far off: over the static scene the PSNR is the map's 42.11 dB,
// over the whole frame far lower. Frame 0 has the person and their mask, frame 1 no person and
// an all-zero mask (static = whole frame), frame 2 the person and no mask (not measured). The
// left eighth of every frame has no depth.
TEST_F(RenderReportTest, PsnrOverTheStaticSceneLeavesThePersonMaskOut) {
  const fs::path d = dir_ / "person_mask";
  fs::create_directories(d);
  fs::copy_file(dir_ / pipeline::kMapFile, d / pipeline::kMapFile);
  const Trajectory all = load_trajectory_file((dir_ / pipeline::kTrajectoryFile).string());
  ASSERT_GE(all.poses.size(), 21u);
  std::vector<io::TumPose> est;
  for (const std::size_t i : {0u, 10u, 20u}) {
    const TimedPose& p = all.poses[i];
    est.push_back({p.t_s, p.T_w_x.translation(), Eigen::Quaterniond(p.T_w_x.linear())});
  }
  io::write_tum_trajectory((d / pipeline::kTrajectoryFile).string(), est);
  // The poses as the evaluation reads them back, to render exactly what it renders.
  const Trajectory cam = load_trajectory_file((d / pipeline::kTrajectoryFile).string());
  const mapping::GaussianMap map = mapping::read_gaussian_ply((d / pipeline::kMapFile).string());
  const int w = camera_.width_px, h = camera_.height_px;
  const auto n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  const std::string rec = (d / "seq.mcap").string();
  {
    io::RecordingWriter writer(rec, io::RecordingWriterOptions{});
    for (std::size_t f = 0; f < cam.poses.size(); ++f) {
      const auto t_ns = static_cast<std::int64_t>(std::llround(cam.poses[f].t_s * 1e9));
      writer.ground_truth(t_ns, cam.poses[f].T_w_x * T_b_c_.inverse());
      std::vector<std::uint8_t> colour = render_u8(map, camera_, cam.poses[f].T_w_x);
      std::vector<std::uint8_t> person(n, 0);
      std::vector<float> depth_m(n, 1.5f);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const std::size_t p = static_cast<std::size_t>(y) * w + x;
          if (x < w / 8) depth_m[p] = 0.0f;
          // Frames 0 and 2: a person in the middle third, close enough to fill 3/4 of its height.
          const bool on_person = f != 1 && x >= w / 3 && x < 2 * w / 3 && y >= h / 4;
          person[p] = on_person ? 255 : 0;
          for (int c = 0; c < 3; ++c) {
            std::uint8_t& v = colour[3 * p + static_cast<std::size_t>(c)];
            v = static_cast<std::uint8_t>(on_person ? v + 128 : v < 128 ? v + 2 : v - 2);
          }
        }
      writer.frame(t_ns, camera_, colour, false, depth_m);
      if (f != 2) writer.dynamic_mask(t_ns, w, h, person);
    }
    writer.close();
  }
  ReportOptions opt = options(d, pipeline::kTrajectoryFile);
  opt.gt_path = rec;
  opt.quality.every = 1;
  const ReportResult r = write_report(opt);
  ASSERT_TRUE(r.quality_measured);
  const QualitySet& q = r.quality.every_nth;
  ASSERT_EQ(q.frames(), 3u);
  ASSERT_EQ(q.psnr_static_db.size(), 3u);
  ASSERT_EQ(q.psnr_static_valid_depth_db.size(), 3u);
  const double map_db = 20.0 * std::log10(255.0 / 2.0);
  std::cout << "frame with a person: PSNR " << q.psnr_db[0] << " dB, valid depth "
            << q.psnr_valid_depth_db[0] << " dB; static " << q.psnr_static_db[0]
            << " dB, static valid depth " << q.psnr_static_valid_depth_db[0] << " dB\n";
  // Frame 0: the person pixels count in the whole frame, not over the static scene.
  EXPECT_LT(q.psnr_db[0], 20.0);
  EXPECT_LT(q.psnr_valid_depth_db[0], 20.0);
  EXPECT_NEAR(q.psnr_static_db[0], map_db, 1e-6);
  EXPECT_NEAR(q.psnr_static_valid_depth_db[0], map_db, 1e-6);
  // Frame 1: an empty mask, so the static figures are the existing ones.
  EXPECT_NEAR(q.psnr_db[1], map_db, 1e-6);
  EXPECT_NEAR(q.psnr_static_db[1], q.psnr_db[1], 1e-9);
  EXPECT_DOUBLE_EQ(q.psnr_static_valid_depth_db[1], q.psnr_valid_depth_db[1]);
  // Frame 2: the same person but no mask: not measured, the existing figures as frame 0's.
  EXPECT_TRUE(std::isnan(q.psnr_static_db[2]));
  EXPECT_TRUE(std::isnan(q.psnr_static_valid_depth_db[2]));
  EXPECT_NEAR(q.psnr_db[2], q.psnr_db[0], 1.0);
  EXPECT_EQ(q.frames_with_dynamic_mask(), 2u);
  EXPECT_NEAR(q.mean_psnr_static_db(), map_db, 1e-6);
  EXPECT_NEAR(q.mean_psnr_static_valid_depth_db(), map_db, 1e-6);

  // `vigs eval run`'s JSON: means over the frames with a mask, per frame null without one.
  const auto j = nlohmann::json::parse(report_json(r, opt));
  const auto& s = j.at("quality").at("every_nth");
  EXPECT_EQ(s.at("frames_with_dynamic_mask").get<int>(), 2);
  EXPECT_NEAR(s.at("psnr_static_db").get<double>(), map_db, 1e-3);
  EXPECT_NEAR(s.at("psnr_static_valid_depth_db").get<double>(), map_db, 1e-3);
  const auto& per_frame = s.at("per_frame");
  ASSERT_EQ(per_frame.at("psnr_static_db").size(), 3u);
  ASSERT_EQ(per_frame.at("psnr_static_valid_depth_db").size(), 3u);
  EXPECT_NEAR(per_frame["psnr_static_db"][0].get<double>(), map_db, 1e-3);
  EXPECT_NEAR(per_frame["psnr_static_valid_depth_db"][1].get<double>(), map_db, 1e-3);
  EXPECT_TRUE(per_frame["psnr_static_db"][2].is_null());
  EXPECT_TRUE(per_frame["psnr_static_valid_depth_db"][2].is_null());
  // and the report's table.
  const std::string md = read_all(r.report_path);
  EXPECT_NE(md.find(" | 2 | 42.11 | 42.11 |\n"), std::string::npos) << md;

  // The first suite's recording has masks too, all zero (no people): static = whole frame.
  const ReportResult plain = write_report(options(dir_, pipeline::kTrajectoryFile));
  const QualitySet& p = plain.quality.every_nth;
  ASSERT_EQ(p.frames_with_dynamic_mask(), p.frames());
  for (std::size_t i = 0; i < p.frames(); ++i) {
    EXPECT_NEAR(p.psnr_static_db[i], p.psnr_db[i], 1e-9) << i;
    EXPECT_DOUBLE_EQ(p.psnr_static_valid_depth_db[i], p.psnr_valid_depth_db[i]) << i;
  }
}

}  // namespace
}  // namespace vigs::eval
