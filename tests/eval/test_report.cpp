#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/config/robot_config.hpp"
#include "eval/mcap_trajectory.hpp"
#include "eval/report.hpp"
#include "eval/trajectory_file.hpp"
#include "io/tum_trajectory.hpp"
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

/// A two-second simulated recording and an "estimate" made from its ground truth camera
/// poses at 20 Hz with a known 10 cm offset along x, so the expected ATE is known exactly.
class ReportTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One folder per process: ctest runs each test of this suite as its own process.
    dir_ = fs::path(::testing::TempDir()) / ("vigs_report_test_" + std::to_string(getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    config::RobotConfig cfg;
    cfg.sim.preset = "apartment";
    cfg.sim.humans = 0;
    cfg.sim.seconds = 2.0;
    sim_ = new sim::Simulator(cfg);
    mcap_ = (dir_ / "seq.mcap").string();
    sim::McapSink sink(mcap_, {});
    sim_->run(sink);
    sink.close();
    std::vector<io::TumPose> est;
    for (int i = 0; i <= 40; ++i) {
      const double t = 0.05 * i;
      const geometry::Pose T_w_c = sim_->camera_pose(t);
      io::TumPose p;
      p.t_s = t;
      p.p_w_m = T_w_c.translation() + Eigen::Vector3d(0.1, 0.0, 0.0);
      p.q_w = Eigen::Quaterniond(T_w_c.linear());
      est.push_back(p);
    }
    io::write_tum_trajectory((dir_ / "trajectory.tum").string(), est);
  }
  static void TearDownTestSuite() {
    fs::remove_all(dir_);
    delete sim_;
    sim_ = nullptr;
  }

  static inline fs::path dir_;
  static inline std::string mcap_;
  static inline sim::Simulator* sim_ = nullptr;
};

TEST_F(ReportTest, GroundTruthFromTheRecordingMatchesTheSimulator) {
  const Trajectory gt = load_mcap_trajectory(mcap_, std::string(io::topics::kBodyPose.name));
  ASSERT_EQ(gt.poses.size(), 401u);  // 2 s at 200 Hz
  EXPECT_TRUE(gt.poses[300].T_w_x.isApprox(sim_->body_pose(1.5), 1e-9));
  EXPECT_THROW(load_mcap_trajectory(mcap_, "/nope"), TrajectoryFileError);
}

TEST_F(ReportTest, WritesReportWithAteRpeAndPlots) {
  ReportOptions opt;
  opt.results_dir = dir_.string();
  opt.gt_path = mcap_;
  opt.T_b_c = sim_->T_b_c();
  opt.ate.align = Alignment::kNone;
  const ReportResult r = write_report(opt);
  EXPECT_EQ(r.ate.pairs, 41u);
  EXPECT_NEAR(r.ate.stats.rmse, 0.1, 1e-9);  // the known offset, camera frame compared
  EXPECT_NEAR(r.ate.stats.max, 0.1, 1e-9);
  EXPECT_LT(r.rpe_frame.translation_m.max, 1e-9);  // a constant offset has no relative error
  const std::string md = read_all(r.report_path);
  EXPECT_NE(md.find("| ATE translation [m] | 41 | 0.1000 |"), std::string::npos) << md;
  EXPECT_NE(md.find("LPIPS"), std::string::npos);
  EXPECT_NE(md.find("PSNR and SSIM"), std::string::npos);
  ASSERT_EQ(r.plots.size(), 2u) << (r.warnings.empty() ? "" : r.warnings.front());
  for (const auto& p : r.plots) {
    const std::string png = read_all(p);
    ASSERT_GT(png.size(), 1000u) << p;
    EXPECT_EQ(png.substr(1, 3), "PNG") << p;
  }
  // se3 alignment removes the constant offset; body-frame comparison sees the lever arm.
  opt.ate.align = Alignment::kSe3;
  EXPECT_LT(write_report(opt).ate.stats.rmse, 1e-6);
  opt.ate.align = Alignment::kNone;
  opt.estimate_is_camera = false;
  opt.plots = false;
  EXPECT_GT(write_report(opt).ate.stats.rmse, 0.1);
}

TEST_F(ReportTest, MissingEstimateIsAClearError) {
  ReportOptions opt;
  opt.results_dir = dir_.string();
  opt.gt_path = mcap_;
  opt.estimate_name = "nothing.tum";
  try {
    write_report(opt);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nothing.tum: no estimated trajectory"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace vigs::eval
