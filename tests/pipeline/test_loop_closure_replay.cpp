// tracking.loop_closure in lockstep replay: the simulated office's whole loop (the route comes
// back to its start after about 110 s) at 240x160, 4 people. The loop closer must close it,
// correct the trajectory below the odometry's own error (frames_odometry, the poses as
// tracked), and give the same trajectory twice.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "pipeline/lockstep_replay.hpp"
#include "pipeline/recorded_motion.hpp"
#include "sim_sequence.hpp"

namespace vigs::pipeline {
namespace {

class LoopClosureReplay : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir();
    cfg_ = testing::small_office(125.0);
    cfg_.sim.humans = 4;
    testing::simulate(cfg_, dir_->file("loop.mcap"));
    motion_ = new RecordedMotion(read_recorded_motion(dir_->file("loop.mcap")));
  }
  static void TearDownTestSuite() {
    delete motion_;
    delete dir_;
  }
  static ReplayResult replay() {
    config::RobotConfig cfg = cfg_;
    cfg.tracking.loop.enabled = true;
    return replay_recording(dir_->file("loop.mcap"), cfg, ReplayOptions{});
  }
  static inline testing::TempDir* dir_ = nullptr;
  static inline config::RobotConfig cfg_;
  static inline RecordedMotion* motion_ = nullptr;
};

TEST_F(LoopClosureReplay, ClosesTheOfficeLoopAndCorrectsTheTrajectory) {
  const ReplayResult on = replay();
  ASSERT_TRUE(on.loop.has_value());
  EXPECT_GE(on.loop->closures, 5) << "attempts " << on.loop->attempts;
  EXPECT_LE(on.loop->rejected, on.loop->attempts / 2);

  ASSERT_EQ(on.frames_odometry.size(), on.frames.size());
  std::vector<TrackedFrame> odometry = on.frames;
  for (std::size_t i = 0; i < odometry.size(); ++i) odometry[i].T_w_c = on.frames_odometry[i];
  const double ate_off = testing::camera_ate(*motion_, odometry, cfg_).stats.rmse;
  const double ate_on = testing::camera_ate(*motion_, on.frames, cfg_).stats.rmse;
  EXPECT_LT(ate_on, 0.8 * ate_off) << "odometry " << ate_off << " m";

  // Lockstep: the corrected trajectory is the same twice.
  const ReplayResult again = replay();
  ASSERT_EQ(again.frames.size(), on.frames.size());
  for (std::size_t i = 0; i < on.frames.size(); ++i) {
    ASSERT_TRUE(again.frames[i].T_w_c.isApprox(on.frames[i].T_w_c, 0.0)) << "frame " << i;
  }
  std::printf("loop closure over %zu frames: ATE %.3f m -> %.3f m, %lld closures of %lld\n",
              on.frames.size(), ate_off, ate_on, static_cast<long long>(on.loop->closures),
              static_cast<long long>(on.loop->attempts));
}

}  // namespace
}  // namespace vigs::pipeline
