// After tracking.reinit_after_lost_frames lost frames the tracker restarts its local map, and
// the odometry starts the IMU state again there, as at the first frame: at rest, at the restart
// pose. The first frame sees a wall; the next ones have no valid depth (every one of them is
// lost) while the IMU reports a moving body, so the state the IMU alone carries drifts away;
// the restart must not keep it.
#include <gtest/gtest.h>

#include "core/config/robot_config.hpp"
#include "core/types/image.hpp"
#include "core/types/rgbd_view.hpp"
#include "inertial/synthetic_motion.hpp"
#include "pipeline/odometry.hpp"

namespace vigs::pipeline {
namespace {

constexpr std::int64_t kFramePeriodNs = 50'000'000;
constexpr std::int64_t kImuPeriodNs = 5'000'000;
constexpr int kLostBeforeRestart = 3;

struct Outcome {
  long restarts = 0;
  long reinitializations = 0;
  Eigen::Vector3d v_after_restart_mps = Eigen::Vector3d::Constant(-1.0);
  geometry::Pose T_w_c_restart = geometry::Pose::Identity();  // the restarted map's first pose
  geometry::Pose T_w_b_state = geometry::Pose::Identity();    // the IMU state just after it
  geometry::Pose T_b_c = geometry::Pose::Identity();
};

Outcome run_frames(tracking::InitialGuessMode guess, FusionMode fusion) {
  config::RobotConfig cfg;
  cfg.camera.width_px = 64;
  cfg.camera.height_px = 48;
  cfg.camera.fx_px = cfg.camera.fy_px = 50.0;
  cfg.camera.cx_px = 32.0;
  cfg.camera.cy_px = 24.0;
  cfg.tracking.reinit_after_lost_frames = kLostBeforeRestart;
  OdometryOptions opt;
  opt.guess = guess;
  opt.fusion = fusion;
  Odometry odometry(cfg, PinholeCamera::from_settings(cfg.camera), opt);

  ImageF32 wall(64, 48, 1);
  for (float& d : wall.data) d = 2.0f;
  const ImageF32 no_depth(64, 48, 1);  // zeros: no valid pixel
  ImageU8 grey(64, 48, 3);
  for (auto& c : grey.data) c = 128;
  const inertial::SyntheticMotion motion;  // ~1 m/s: the IMU-only state drifts fast
  const Eigen::Vector3d g_w(0, 0, -9.81);
  std::int64_t t_imu_ns = 0;
  Outcome r;
  r.T_b_c = inertial::InertialFrontendOptions::from(cfg.imu, cfg.extrinsics, cfg.inertial).T_b_c;
  for (int k = 0; k <= kLostBeforeRestart; ++k) {
    const std::int64_t t_ns = 1'000'000'000 + k * kFramePeriodNs;
    for (; t_imu_ns <= t_ns + 2 * kImuPeriodNs; t_imu_ns += kImuPeriodNs) {
      EXPECT_TRUE(odometry.add_imu(motion.sample(t_imu_ns, g_w)));
    }
    const TrackedFrame f = odometry.track(rgbd_view(t_ns, k == 0 ? wall : no_depth, grey));
    EXPECT_FALSE(f.pose_from_gicp) << "frame " << k;
    if (f.reinitialized) {
      r.T_w_c_restart = f.T_w_c;
      r.v_after_restart_mps = odometry.inertial().velocity_w_mps();
      r.T_w_b_state = odometry.inertial().state_at_reset().T_w_b();
    }
  }
  r.restarts = odometry.inertial().counters().restarts;
  r.reinitializations = odometry.counters().reinitializations;
  return r;
}

class OdometryRestart : public ::testing::TestWithParam<FusionMode> {};

TEST_P(OdometryRestart, AMapRestartStartsTheImuStateAgainAtRestAtTheRestartPose) {
  const Outcome r = run_frames(tracking::InitialGuessMode::imu, GetParam());
  ASSERT_EQ(r.reinitializations, 1) << "restarted after " << kLostBeforeRestart << " lost frames";
  EXPECT_EQ(r.restarts, 1);
  EXPECT_EQ(r.v_after_restart_mps.norm(), 0.0) << r.v_after_restart_mps.transpose();
  // The IMU state is the restart pose's body.
  const geometry::PoseError e = geometry::pose_error(r.T_w_b_state * r.T_b_c, r.T_w_c_restart);
  EXPECT_LT(e.translation_m, 1e-9);
  EXPECT_LT(e.rotation_rad, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(BothFusionModes, OdometryRestart,
                         ::testing::Values(FusionMode::paper, FusionMode::fused),
                         [](const auto& mode) { return std::string(to_string(mode.param)); });

TEST(OdometryRestartWithoutImu, NoImuStateIsTouched) {
  const Outcome r = run_frames(tracking::InitialGuessMode::previous_pose, FusionMode::paper);
  EXPECT_EQ(r.reinitializations, 1);
  EXPECT_EQ(r.restarts, 0);
}

}  // namespace
}  // namespace vigs::pipeline
