// Accuracy behaviour of the odometry on short simulated office sequences (240x160):
//  - GICP is not a no-op: with it the ATE is below half the IMU-only (every GICP result
//    rejected) ATE;
//  - fused (IMU prior in GICP, 15-state filter) beats the paper's guess-and-reset scheme;
//  - walking people: the moving-point rejection (confirmed local map, free-space test, bounded
//    kernel) keeps the ATE near the empty office's, and people are flagged moving;
//  - not_converged GICP results are counted apart from converged ones;
//  - every tracked frame exports a finite, positive definite pose covariance.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cstdio>

#include "pipeline/lockstep_replay.hpp"
#include "pipeline/odometry.hpp"
#include "tests/pipeline/sim_sequence.hpp"

namespace vigs::pipeline {
namespace {

using testing::TempDir;

struct Sequence {
  TempDir dir;
  config::RobotConfig cfg;
  std::string path;
  RecordedMotion motion;
  Sequence(double seconds, int humans) {
    cfg = testing::small_office(seconds);
    cfg.sim.humans = humans;
    path = dir.file("office.mcap");
    testing::simulate(cfg, path);
    motion = read_recorded_motion(path);
  }
  double ate(const config::RobotConfig& c, const ReplayOptions& opt, ReplayResult* out = nullptr) {
    ReplayResult r = replay_recording(path, c, opt);
    const double rmse = testing::camera_ate(motion, r.frames, c).stats.rmse;
    if (out != nullptr) *out = std::move(r);
    return rmse;
  }
};

ReplayOptions imu(FusionMode fusion) {
  ReplayOptions o;
  o.guess = tracking::InitialGuessMode::imu;
  o.fusion = fusion;
  return o;
}

// 12 s: 2 s at rest, then 10 s (about 11 m) of corridor walking.
class EmptyOffice : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { seq_ = new Sequence(12.0, 0); }
  static void TearDownTestSuite() {
    delete seq_;
    seq_ = nullptr;
  }
  static Sequence* seq_;
};
Sequence* EmptyOffice::seq_ = nullptr;

TEST_F(EmptyOffice, GicpIsNotANoOpAndFusedBeatsPaper) {
  ReplayResult fused_r;
  const double fused = seq_->ate(seq_->cfg, imu(FusionMode::fused), &fused_r);
  const double paper = seq_->ate(seq_->cfg, imu(FusionMode::paper));
  config::RobotConfig imu_only_cfg = seq_->cfg;
  imu_only_cfg.tracking.max_correction_m = 0.0;  // every GICP result rejected: dead reckoning
  ReplayResult imu_only_r;
  const double imu_only = seq_->ate(imu_only_cfg, imu(FusionMode::paper), &imu_only_r);
  std::printf("ATE rmse: fused %.4f m, paper %.4f m, IMU only %.4f m\n", fused, paper, imu_only);
  EXPECT_EQ(imu_only_r.counters.tracked, 0);
  EXPECT_EQ(fused_r.counters.lost, 0);
  EXPECT_LT(fused, 0.5 * imu_only);
  EXPECT_LT(paper, 0.5 * imu_only);
  EXPECT_LT(fused, kFusedOverPaper * paper);

  // not_converged is counted apart: a one-iteration budget leaves most frames unconverged.
  EXPECT_LE(fused_r.counters.not_converged, fused_r.counters.tracked / 10);
  config::RobotConfig one_iter = seq_->cfg;
  one_iter.tracking.max_iterations = 1;
  ReplayOptions o = imu(FusionMode::fused);
  o.max_frames = 120;
  const ReplayResult r1 = replay_recording(seq_->path, one_iter, o);
  long not_converged = 0;
  for (const TrackedFrame& f : r1.frames)
    if (f.status == tracking::TrackingStatus::tracked &&
        f.gicp_verdict == tracking::GicpVerdict::not_converged)
      ++not_converged;
  EXPECT_EQ(r1.counters.not_converged, not_converged);
  EXPECT_GT(r1.counters.not_converged, r1.counters.tracked / 2);

  // Covariance exported for every tracked frame, symmetric positive definite.
  for (const TrackedFrame& f : fused_r.frames) {
    if (!f.pose_from_gicp) continue;
    ASSERT_TRUE(f.covariance_valid) << f.t_ns;
    const Eigen::Map<const Eigen::Matrix<double, 6, 6, Eigen::RowMajor>> C(f.covariance);
    ASSERT_TRUE(C.allFinite());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(C).eigenvalues()(0),
              0.0);
  }
}

TEST(MovingPeople, RejectionKeepsTheAteNearTheEmptyOfficesAndFlagsPeople) {
  Sequence seq(12.0, 24);
  ReplayResult with_r;
  const double with = seq.ate(seq.cfg, imu(FusionMode::fused), &with_r);
  config::RobotConfig off = seq.cfg;  // no rejection: every point used at once, huber
  off.tracking.local_map_confirm_distance_m = 0.0;
  off.tracking.moving_margin_m = 0.0;
  ReplayResult without_r;
  const double without = seq.ate(off, imu(FusionMode::fused), &without_r);
  std::printf("24 people: ATE rmse %.4f m with rejection, %.4f m without; moving points %ld\n",
              with, without, with_r.counters.moving_points);
  EXPECT_LT(with, kMovingBound);
  EXPECT_LT(with, kMovingGain * without);
  EXPECT_GT(with_r.counters.moving_points, 0);
  EXPECT_EQ(without_r.counters.moving_points, 0);
}

}  // namespace
}  // namespace vigs::pipeline
