// The tracker restarts its local map after tracking.reinit_after_lost_frames lost frames in a
// row. On a simulated office the guess is the ground truth for 40 frames, then the ground truth
// moved by 3 m (an IMU that drifted while the tracker was lost): GICP cannot reconcile the old
// map with it and every frame is lost. With the restart the track goes on from the moved pose
// (the map starts again there, so GICP agrees with the guess); without it, it never comes back.
#include <gtest/gtest.h>

#include "core/config/robot_config.hpp"
#include "sim/simulator.hpp"
#include "tests/pipeline/sim_sequence.hpp"
#include "tracking/settings_from_config.hpp"
#include "tracking/tracker.hpp"

namespace vigs::pipeline {
namespace {

constexpr int kGoodFrames = 40;
constexpr int kFrames = 100;

struct Outcome {
  int lost_after_jump = 0;     // frames kGoodFrames.. lost
  int tracked_after_jump = 0;  // frames kGoodFrames.. tracked (pose from GICP)
  int reinitialized = 0;
  int first_tracked_after_jump = -1;
};

Outcome track_with_a_jump(int reinit_after_lost_frames) {
  config::RobotConfig cfg = testing::small_office(kFrames / 20.0);
  cfg.tracking.reinit_after_lost_frames = reinit_after_lost_frames;
  const sim::Simulator simulator(cfg);
  const PinholeCamera camera = simulator.camera();
  tracking::Tracker tracker(camera, tracking::tracker_setting(cfg.tracking));
  sim::RgbdFrame frame;
  ImageF32 depth(camera.width_px, camera.height_px, 1);
  ImageU8 rgb(camera.width_px, camera.height_px, 3);
  Outcome o;
  for (int j = 0; j < kFrames; ++j) {
    const double t_s = j / cfg.camera.rate_hz;
    simulator.render_at(t_s, static_cast<std::uint64_t>(j), frame);
    depth.data = frame.depth_m;
    rgb.data = frame.color;
    geometry::Pose guess = simulator.camera_pose(t_s);
    if (j >= kGoodFrames) guess.pretranslate(Eigen::Vector3d(2.0, 2.0, 1.0));
    const tracking::TrackingOutput out =
        tracker.track(static_cast<std::int64_t>(j) * 50'000'000, depth, rgb, &guess);
    o.reinitialized += out.reinitialized;
    if (j < kGoodFrames) {
      EXPECT_TRUE(j == 0 || out.pose_from_gicp) << "frame " << j;
      continue;
    }
    if (out.pose_from_gicp) {
      ++o.tracked_after_jump;
      if (o.first_tracked_after_jump < 0) o.first_tracked_after_jump = j;
    } else {
      ++o.lost_after_jump;
    }
  }
  return o;
}

TEST(TrackerReinit, TheTrackGoesOnAfterTheMapIsRestarted) {
  const Outcome with = track_with_a_jump(10);
  EXPECT_EQ(with.reinitialized, 1);
  EXPECT_EQ(with.lost_after_jump, 10) << "lost until the restart, tracked from the next frame";
  EXPECT_EQ(with.first_tracked_after_jump, kGoodFrames + 10);
  EXPECT_EQ(with.tracked_after_jump, kFrames - kGoodFrames - 10);

  const Outcome without = track_with_a_jump(0);
  EXPECT_EQ(without.reinitialized, 0);
  EXPECT_EQ(without.tracked_after_jump, 0) << "the old map never matches the moved guess";
}

}  // namespace
}  // namespace vigs::pipeline
