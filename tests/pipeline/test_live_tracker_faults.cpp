// LiveTracker's backlog and fault policies, driven tick by tick on the test thread with frames
// pushed by hand: skip to the newest frame (counted, flagged), a frame stamped before its
// predecessor (released, counted in the tracker and the 1 Hz status, the next pose flagged), the
// drivers' corrupt IMU bytes and camera losses (the first pose after each flagged), a lost frame
// (propagated) and the local map restarting (flagged), the end marker ending the stream.
#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "core/config/robot_config.hpp"
#include "pipeline/live_status.hpp"
#include "pipeline/live_tracker.hpp"
#include "rt/periodic_task.hpp"
#include "rt/thread_table.hpp"

namespace vigs::pipeline {
namespace {

/// The drivers' fault totals, set by hand between ticks (the test thread is the tracker's).
struct FakeDriverFaults final : DriverFaultCounts {
  [[nodiscard]] std::uint64_t imu_corrupt() const noexcept override { return imu_corrupt_count; }
  [[nodiscard]] std::uint64_t camera_losses() const noexcept override { return camera_loss_count; }
  std::uint64_t imu_corrupt_count = 0;
  std::uint64_t camera_loss_count = 0;
};

std::optional<std::uint64_t> status_fault(const dds::StatusSnapshot& st, const std::string& name) {
  for (std::uint32_t i = 0; i < st.fault_count; ++i) {
    if (name == st.faults[i].name) return st.faults[i].count;
  }
  return std::nullopt;
}

class LiveTrackerFaults : public ::testing::Test {
 protected:
  LiveTrackerFaults() {
    cfg_.camera.width_px = 64;
    cfg_.camera.height_px = 48;
    cfg_.camera.fx_px = cfg_.camera.fy_px = 50.0;
    cfg_.camera.cx_px = 32.0;
    cfg_.camera.cy_px = 24.0;
    settings_.camera = PinholeCamera::from_settings(cfg_.camera);
    settings_.odometry.guess = tracking::InitialGuessMode::previous_pose;  // no IMU needed
    make_tracker();
  }
  void make_tracker() {
    tracker_.emplace(cfg_, settings_,
                     LiveTrackerRings{pool_, frames_, imu_, poses_, results_, nullptr});
  }

  /// Pushes a frame (a flat wall 2 m away, grey) stamped t_ns.
  void push(std::int64_t t_ns) {
    const rt::FrameHandle h = pool_.acquire();
    ASSERT_TRUE(h.valid());
    rt::Frame& f = pool_.frame(h);
    for (auto& d : f.depth) d = 2000;
    for (auto& c : f.colour) c = 128;
    f.t_ns = t_ns;
    ASSERT_TRUE(frames_.try_push(h));
  }
  std::vector<PoseSample> poses() {
    std::vector<PoseSample> out;
    PoseSample p;
    while (poses_.try_pop(p)) out.push_back(p);
    return out;
  }

  FakeDriverFaults driver_faults_;  // outlives the tracker
  config::RobotConfig cfg_;
  LiveTrackerSettings settings_;
  rt::FramePool pool_{{.slots = 8, .width = 64, .height = 48, .colour_channels = 3}};
  rt::SpscRing<rt::FrameHandle> frames_{4};
  rt::SpscRing<ImuSample> imu_{16};
  rt::SpscRing<PoseSample> poses_{16};
  rt::SpscRing<LiveFrameResult> results_{16};
  std::optional<LiveTracker> tracker_;
};

TEST_F(LiveTrackerFaults, SkipsToNewestAndFlagsIt) {
  push(1'000'000'000);
  tracker_->tick();
  push(1'050'000'000);
  push(1'100'000'000);
  push(1'150'000'000);
  tracker_->tick();  // three queued: the newest is tracked, two skipped
  const auto p = poses();
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[1].t_ns, 1'150'000'000);
  EXPECT_EQ(p[1].frame_index, 1u);
  EXPECT_NE(p[1].flags & kPoseFlagFramesSkipped, 0u);
  EXPECT_EQ(p[0].flags & kPoseFlagFramesSkipped, 0u);
  EXPECT_EQ(tracker_->counters().skipped, 2u);
  EXPECT_EQ(pool_.available(), pool_.capacity());  // every slot came back
}

TEST_F(LiveTrackerFaults, OutOfOrderFrameIsDroppedCountedAndFlagged) {
  push(2'000'000'000);
  tracker_->tick();
  push(1'900'000'000);  // older than the last tracked frame
  tracker_->tick();
  push(2'100'000'000);
  tracker_->tick();
  const auto p = poses();
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[1].t_ns, 2'100'000'000);
  EXPECT_NE(p[1].flags & kPoseFlagOutOfOrder, 0u);
  EXPECT_EQ(tracker_->counters().out_of_order, 1u);
  EXPECT_EQ(tracker_->counters().frames, 2u);
  EXPECT_EQ(pool_.available(), pool_.capacity());
  // The count reaches the 1 Hz status (rt/vigs/status) as tracker.out_of_order.
  const rt::PeriodicTask task(rt::thread_spec("tracker"), [] {});
  const LiveStatusSources sources{&task, nullptr, &*tracker_, nullptr, &frames_,
                                  &imu_, &poses_, nullptr,    nullptr, nullptr};
  EXPECT_EQ(status_fault(make_status_snapshot(sources, 1'000), "tracker.out_of_order"), 1u);
}

// The drivers count their faults on their own threads; the tracker flags the first pose after a
// count grew, and only that one.
TEST_F(LiveTrackerFaults, DriverFaultsFlagTheFirstPoseAfterThem) {
  settings_.driver_faults = &driver_faults_;
  make_tracker();
  const auto track = [&](std::int64_t t_ns) {
    push(t_ns);
    tracker_->tick();
  };
  // Bytes skipped to the first header when the port was opened mid-stream: the baseline at the
  // first pose, not a fault.
  driver_faults_.imu_corrupt_count = 40;
  track(3'000'000'000);
  driver_faults_.imu_corrupt_count = 43;  // a bad checksum and the bytes skipped to resync
  track(3'050'000'000);
  track(3'100'000'000);
  driver_faults_.camera_loss_count = 1;  // lost and reopened before the next frame
  track(3'150'000'000);
  track(3'200'000'000);
  driver_faults_.imu_corrupt_count = 45;
  driver_faults_.camera_loss_count = 2;
  track(3'250'000'000);
  track(3'300'000'000);
  const auto p = poses();
  ASSERT_EQ(p.size(), 7u);
  constexpr std::uint32_t kDriverFlags = kPoseFlagImuCorrupt | kPoseFlagCameraReopened;
  EXPECT_EQ(p[0].flags & kDriverFlags, 0u);
  EXPECT_EQ(p[1].flags & kDriverFlags, kPoseFlagImuCorrupt);
  EXPECT_EQ(p[2].flags & kDriverFlags, 0u);
  EXPECT_EQ(p[3].flags & kDriverFlags, kPoseFlagCameraReopened);
  EXPECT_EQ(p[4].flags & kDriverFlags, 0u);
  EXPECT_EQ(p[5].flags & kDriverFlags, kDriverFlags);
  EXPECT_EQ(p[6].flags & kDriverFlags, 0u);
}

// The flat wall leaves GICP a degenerate problem (a plane): with no prior, every frame after the
// first is lost, its pose the guess; after two lost frames in a row the local map restarts.
TEST_F(LiveTrackerFaults, LostFramesArePropagatedAndAMapRestartIsFlagged) {
  cfg_.tracking.reinit_after_lost_frames = 2;
  make_tracker();
  for (int i = 0; i < 3; ++i) {
    push(1'000'000'000 + i * 50'000'000);
    tracker_->tick();
  }
  const auto p = poses();
  ASSERT_EQ(p.size(), 3u);
  EXPECT_EQ(p[0].source, PoseSource::kInitial);
  EXPECT_EQ(p[1].source, PoseSource::kImuPropagated);
  EXPECT_EQ(p[2].source, PoseSource::kImuPropagated);
  EXPECT_NE(p[1].flags & kPoseFlagDegenerate, 0u);
  EXPECT_EQ(p[1].flags & kPoseFlagMapRestarted, 0u);
  EXPECT_NE(p[2].flags & kPoseFlagMapRestarted, 0u);  // the second lost frame in a row
  EXPECT_TRUE(p[2].keyframe);                         // the restarted map's first keyframe
  EXPECT_EQ(tracker_->odometry_counters().reinitializations, 1);
}

TEST_F(LiveTrackerFaults, EndMarkerEndsTheStream) {
  push(1'000'000'000);
  ASSERT_TRUE(frames_.try_push(rt::FrameHandle{}));
  tracker_->tick();
  tracker_->tick();
  EXPECT_TRUE(tracker_->done());
  LiveFrameResult r;
  ASSERT_TRUE(results_.try_pop(r));
  EXPECT_FALSE(r.end_of_stream);
  ASSERT_TRUE(results_.try_pop(r));
  EXPECT_TRUE(r.end_of_stream);
}

}  // namespace
}  // namespace vigs::pipeline
