// tracking.loop_closure in lockstep replay: the simulated office's whole loop (the route comes
// back to its start after about 110 s) at 240x160, 4 people. The loop closer must close it,
// correct the trajectory below the odometry's own error (frames_odometry, the poses as
// tracked), without adding a jump of its own between neighbouring frames, and give the same
// trajectory twice. With mapping, the map follows the closures
// (map_loop_correction.hpp): rendered at the corrected trajectory, the start of the loop, which
// the return walks again, matches its images better than the map that kept the odometry's
// poses does at those poses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "eval/render_quality.hpp"
#include "pipeline/lockstep_replay.hpp"
#include "pipeline/recorded_motion.hpp"
#include "sim_sequence.hpp"

namespace vigs::pipeline {
namespace {

/// The largest translation, over consecutive frames, between the step of `corrected` and the
/// step of `odometry` (each in its earlier frame's camera frame): what the correction added to
/// one frame's motion. A smooth correction spreads a loop's error over the keyframes between
/// the closures; a keyframe pulled on its own by a loop edge makes a step of its own.
double largest_added_step_m(const std::vector<TrackedFrame>& corrected,
                            const std::vector<geometry::Pose>& odometry) {
  double largest = 0.0;
  for (std::size_t i = 1; i < corrected.size(); ++i) {
    const geometry::Pose step_c = corrected[i - 1].T_w_c.inverse() * corrected[i].T_w_c;
    const geometry::Pose step_o = odometry[i - 1].inverse() * odometry[i];
    largest = std::max(largest, (step_o.inverse() * step_c).translation().norm());
  }
  return largest;
}

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
  static ReplayResult replay(int map_iterations = 0, bool follow = true) {
    config::RobotConfig cfg = cfg_;
    cfg.tracking.loop.enabled = true;
    cfg.mapping.follow_loop_closures = follow;
    ReplayOptions o;
    o.map_iterations_per_frame = map_iterations;
    return replay_recording(dir_->file("loop.mcap"), cfg, o);
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
  const double added_step_m = largest_added_step_m(on.frames, on.frames_odometry);
  std::printf("largest step the correction added to one frame: %.2f mm\n", 1e3 * added_step_m);
  // 8.5 mm with each keyframe's own solved correction applied from it to the next (a loop
  // edge moved its keyframe alone), 1.7 mm with those interpolated in time, 0.5 mm with the
  // corrections smoothed along the keyframes as well (LoopCloser::kCorrectionHalfWindow).
  EXPECT_LT(added_step_m, 1e-3);

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

/// Mean PSNR of `map` rendered at `frames` (every 10th recorded frame of the first 20 s, the
/// stretch the route walks again at its end) against the recorded images.
double start_psnr(const mapping::GaussianMap& map, const std::vector<TrackedFrame>& frames,
                  const std::string& mcap) {
  eval::Trajectory T_w_c;
  for (const TrackedFrame& f : frames)
    if (f.t_ns < 20'000'000'000)
      T_w_c.poses.push_back({1e-9 * static_cast<double>(f.t_ns), f.T_w_c});
  eval::RenderQualityOptions opt;
  opt.every = 10;
  opt.side_by_side_rows = 0;
  return eval::measure_render_quality(map, T_w_c, nullptr, mcap, opt).every_nth.mean_psnr_db();
}

TEST_F(LoopClosureReplay, TheMapFollowsTheClosures) {
  const ReplayResult on = replay(1, true);
  const ReplayResult off = replay(1, false);
  ASSERT_TRUE(on.map && off.map);
  ASSERT_TRUE(on.loop && on.loop->closures > 0);
  EXPECT_GT(on.map_moved_by_loops, on.map->size() / 2);  // the whole loop moved a little
  EXPECT_EQ(off.map_moved_by_loops, 0u);
  // the tracking is the same (the map does not feed back into it)
  ASSERT_EQ(on.frames.size(), off.frames.size());
  for (std::size_t i = 0; i < on.frames.size(); ++i)
    ASSERT_TRUE(on.frames[i].T_w_c.isApprox(off.frames[i].T_w_c, 0.0)) << i;
  std::vector<TrackedFrame> odometry = off.frames;
  for (std::size_t i = 0; i < odometry.size(); ++i) odometry[i].T_w_c = off.frames_odometry[i];
  const std::string mcap = dir_->file("loop.mcap");
  const double followed = start_psnr(*on.map, on.frames, mcap);
  const double kept = start_psnr(*off.map, odometry, mcap);
  const double kept_at_corrected = start_psnr(*off.map, off.frames, mcap);
  std::printf(
      "loop start rendered: map following the closures %.2f dB at the corrected poses; "
      "map at the odometry's poses %.2f dB there, %.2f dB at the corrected poses\n",
      followed, kept, kept_at_corrected);
  EXPECT_GT(followed, kept + 0.5);
  EXPECT_GT(followed, kept_at_corrected + 0.5);
}

}  // namespace
}  // namespace vigs::pipeline
