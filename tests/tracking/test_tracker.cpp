// Tracker: ICL-NUIM sequence against the local map in each initial-guess mode, failure
// detection on a single wall, keyframe policy, constant-velocity prediction, config mapping.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/config/diagnostics.hpp"
#include "core/config/yaml_loader.hpp"
#include "io/image_io.hpp"
#include "tracking/settings_from_config.hpp"
#include "tracking/tracker.hpp"

namespace vigs::tracking {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
const std::string kIcl = std::string(VIGS_SHARED_DATA_DIR) + "/icl_nuim_livingroom1/";
const PinholeCamera kIclCamera{640, 480, 525.0, 525.0, 319.5, 239.5};

std::vector<geometry::Pose> icl_poses() {
  std::ifstream in(kIcl + "trajectory.log");
  std::vector<geometry::Pose> poses;
  int a = 0, b = 0, c = 0;
  while (in >> a >> b >> c) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      for (int k = 0; k < 4; ++k) in >> m(r, k);
    }
    poses.emplace_back(geometry::Pose(m));
  }
  return poses;
}

struct IclFrame {
  ImageF32 depth;
  ImageU8 rgb;
};

const std::vector<IclFrame>& icl_frames() {
  static const std::vector<IclFrame> frames = [] {
    std::vector<IclFrame> f;
    for (int i = 0; i < 5; ++i) {
      char name[16];
      std::snprintf(name, sizeof name, "%05d", i);
      f.push_back({io::read_depth_m(kIcl + "depth_" + name + ".png", 0.001),
                   io::read_rgb(kIcl + "color_" + name + ".jpg")});
    }
    return f;
  }();
  return frames;
}

class TrackerModes : public ::testing::TestWithParam<InitialGuessMode> {};

TEST_P(TrackerModes, IclSequenceTrackedAgainstLocalMap) {
  const auto gt = icl_poses();
  ASSERT_GE(gt.size(), 5u);
  Tracker::Setting s = tracker_setting(config::TrackingSettings{});
  s.initial_guess = GetParam();
  Tracker tracker(kIclCamera, s, gt[0]);
  const geometry::Pose perturb =
      geometry::make_pose(Eigen::Vector3d(1.0, -1.0, 1.0).normalized() * 0.3 * kDeg,
                          Eigen::Vector3d(0.003, 0.004, 0.0));
  for (int i = 0; i < 5; ++i) {
    // IMU-quality guess; the first frame anchors the map at the true pose.
    const geometry::Pose imu = i == 0 ? gt[0] : gt[static_cast<std::size_t>(i)] * perturb;
    const TrackingOutput out =
        tracker.track(i * 33'333'333LL, icl_frames()[static_cast<std::size_t>(i)].depth,
                      icl_frames()[static_cast<std::size_t>(i)].rgb, &imu);
    if (i == 0) {
      EXPECT_EQ(out.status, TrackingStatus::initialized);
      EXPECT_TRUE(out.keyframe);
      continue;
    }
    EXPECT_EQ(out.status, TrackingStatus::tracked)
        << "frame " << i << ": " << to_string(out.status);
    EXPECT_TRUE(out.pose_from_gicp);
    EXPECT_FALSE(out.guess_fell_back);
    const geometry::PoseError e = geometry::pose_error(gt[static_cast<std::size_t>(i)], out.T_w_c);
    std::printf("mode %d frame %d: %.2f mm %.3f deg, %d iterations, overlap %.2f%s\n",
                static_cast<int>(GetParam()), i, e.translation_m * 1e3, e.rotation_rad / kDeg,
                out.gicp.iterations, out.gicp.overlap_ratio, out.keyframe ? ", keyframe" : "");
    EXPECT_LT(e.translation_m, 0.01) << "frame " << i;
    EXPECT_LT(e.rotation_rad, 0.3 * kDeg) << "frame " << i;
  }
  EXPECT_GT(tracker.local_map().num_points(), 10000u);
  EXPECT_EQ(tracker.last_keyframe().cloud_c.size(), tracker.last_keyframe().cloud_c.cov_m2.size());
}

INSTANTIATE_TEST_SUITE_P(Modes, TrackerModes,
                         ::testing::Values(InitialGuessMode::imu,
                                           InitialGuessMode::constant_velocity,
                                           InitialGuessMode::previous_pose));

TEST(Tracker, SingleWallIsReportedDegenerateAndTheImuPoseIsKept) {
  const PinholeCamera cam{160, 120, 100.0, 100.0, 79.5, 59.5};
  const ImageF32 wall(160, 120, 1, 2.0f);  // a flat wall 2 m ahead
  Tracker::Setting s = tracker_setting(config::TrackingSettings{});
  s.preprocess.depth.pixel_stride = 2;
  Tracker tracker(cam, s);
  tracker.track(0, wall, ImageU8{});
  const geometry::Pose imu =
      geometry::make_pose(Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(0.05, 0.0, 0.0));
  const TrackingOutput out = tracker.track(50'000'000, wall, ImageU8{}, &imu);
  EXPECT_EQ(out.gicp.verdict, GicpVerdict::degenerate) << out.gicp.eigen_ratio;
  EXPECT_EQ(out.status, TrackingStatus::lost_degenerate);
  EXPECT_FALSE(out.pose_from_gicp);
  EXPECT_FALSE(out.keyframe);
  EXPECT_TRUE(out.T_w_c.isApprox(imu));
}

TEST(Tracker, ImuModeWithoutImuFallsBackToConstantVelocityAndSaysSo) {
  const PinholeCamera cam{160, 120, 100.0, 100.0, 79.5, 59.5};
  const ImageF32 wall(160, 120, 1, 2.0f);
  Tracker tracker(cam, tracker_setting(config::TrackingSettings{}));
  tracker.track(0, wall, ImageU8{});
  const TrackingOutput out = tracker.track(50'000'000, wall, ImageU8{}, nullptr);
  EXPECT_TRUE(out.guess_fell_back);
}

TEST(InitialGuess, ConstantVelocityRepeatsTheLastMotionScaledByTime) {
  const geometry::Pose A =
      geometry::make_pose(Eigen::Vector3d(0.0, 0.1, 0.0), Eigen::Vector3d(1.0, 0.0, 0.0));
  const geometry::Pose step =
      geometry::make_pose(Eigen::Vector3d(0.0, 0.0, 0.02), Eigen::Vector3d(0.1, 0.0, 0.0));
  const geometry::Pose B = A * step;
  const geometry::Pose C = predict_constant_velocity(A, 0, B, 100, 200);
  EXPECT_TRUE(C.isApprox(B * step, 1e-12));
  const geometry::Pose half = predict_constant_velocity(A, 0, B, 100, 150);
  EXPECT_NEAR((B.inverse() * half).translation().x(), 0.05, 1e-12);
  EXPECT_NEAR(geometry::rotation_angle((B.inverse() * half).linear()), 0.01, 1e-12);
}

TEST(KeyframePolicy, OverlapTranslationAndRotationThresholds) {
  KeyframePolicy p;
  p.setting = {0.9, 0.3, 15.0};
  const geometry::Pose I = geometry::Pose::Identity();
  EXPECT_FALSE(p.is_keyframe(0.95, I, I));
  EXPECT_TRUE(p.is_keyframe(0.85, I, I));
  EXPECT_TRUE(p.is_keyframe(
      0.95, I, geometry::make_pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.31, 0, 0))));
  EXPECT_FALSE(p.is_keyframe(
      0.95, I, geometry::make_pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.29, 0, 0))));
  EXPECT_TRUE(p.is_keyframe(
      0.95, I, geometry::make_pose(Eigen::Vector3d(0, 16.0 * kDeg, 0), Eigen::Vector3d::Zero())));
}

TEST(TrackingConfig, YamlSectionMapsOntoComponentSettings) {
  const auto cfg = config::load_config_text(
      "tracking:\n  pixel_stride: 2\n  regularization: plane\n  robust_kernel: cauchy\n"
      "  initial_guess: previous_pose\n  rotation_eps_deg: 0.05\n  local_map_max_voxels: 4096\n",
      "test.yaml");
  const Tracker::Setting s = tracker_setting(cfg.tracking);
  EXPECT_EQ(s.preprocess.depth.pixel_stride, 2);
  EXPECT_EQ(s.preprocess.covariance.regularization, Regularization::plane);
  EXPECT_EQ(s.gicp.kernel, RobustKernel::cauchy);
  EXPECT_EQ(s.initial_guess, InitialGuessMode::previous_pose);
  EXPECT_NEAR(s.gicp.rotation_eps_rad(), 0.05 * kDeg, 1e-15);
  EXPECT_EQ(s.local_map.max_voxels, 4096);
  EXPECT_EQ(s.preprocess.covariance.k_neighbors, 10);  // default kept
  EXPECT_THROW(config::load_config_text("tracking:\n  regularization: sphere\n", "bad.yaml"),
               config::ConfigError);
  EXPECT_THROW(config::load_config_text(
                   "tracking:\n  local_map_voxel_m: 0.05\n  max_correspondence_distance_m: 0.1\n",
                   "bad.yaml"),
               config::ConfigError);
}

}  // namespace
}  // namespace vigs::tracking
