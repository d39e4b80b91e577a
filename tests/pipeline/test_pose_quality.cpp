// A tracked frame's pose quality (pipeline/pose_quality.hpp) and its place in the 1 Hz status
// (pipeline/live_status.hpp): the source of the first, a tracked and a lost frame; the flags a
// frame carries (degenerate, map restarted); the counts of propagated / degenerate / restarted
// poses as status faults, and tracking_state from the newest pose. No DDS traffic.
#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "core/config/robot_config.hpp"
#include "pipeline/live_status.hpp"
#include "pipeline/pose_quality.hpp"
#include "rt/thread_table.hpp"

namespace vigs::pipeline {
namespace {

TEST(PoseQuality, SourceOfTheFirstATrackedAndALostFrame) {
  TrackedFrame f;
  f.pose_from_gicp = false;  // the first frame starts the map at its guess
  EXPECT_EQ(pose_source(f, 0), PoseSource::kInitial);
  EXPECT_EQ(pose_source(f, 1), PoseSource::kImuPropagated);  // lost: the guess
  f.pose_from_gicp = true;
  EXPECT_EQ(pose_source(f, 1), PoseSource::kTracked);
}

TEST(PoseQuality, AFrameCarriesDegenerateAndMapRestarted) {
  TrackedFrame f;
  EXPECT_EQ(frame_pose_flags(f), kPoseFlagNone);
  f.degenerate = true;
  EXPECT_EQ(frame_pose_flags(f), kPoseFlagDegenerate);
  f.degenerate = false;
  f.reinitialized = true;  // tracking.reinit_after_lost_frames restarted the local map here
  EXPECT_EQ(frame_pose_flags(f), kPoseFlagMapRestarted);
}

TEST(PoseQuality, TrackingStateFollowsTheNewestPose) {
  PoseQualityCounts c;
  EXPECT_EQ(tracking_state(c), dds::TrackingState::kStarting);
  c.add(PoseSource::kInitial, kPoseFlagNone);
  EXPECT_EQ(tracking_state(c), dds::TrackingState::kTracking);
  c.add(PoseSource::kImuPropagated, kPoseFlagDegenerate);
  EXPECT_EQ(tracking_state(c), dds::TrackingState::kImuOnly);
  c.add(PoseSource::kImuPropagated, kPoseFlagImuUnavailable | kPoseFlagMapRestarted);
  EXPECT_EQ(tracking_state(c), dds::TrackingState::kLost);
  c.add(PoseSource::kTracked, kPoseFlagDegenerate);
  EXPECT_EQ(tracking_state(c), dds::TrackingState::kTracking);
  EXPECT_EQ(c.poses, 4u);
  EXPECT_EQ(c.imu_propagated, 2u);
  EXPECT_EQ(c.degenerate, 2u);
  EXPECT_EQ(c.map_restarts, 1u);
}

// make_status_snapshot with a tracker and its (unstarted) task: the counts are status faults.
class PoseQualityStatus : public ::testing::Test {
 protected:
  PoseQualityStatus() {
    cfg_.camera.width_px = 64;
    cfg_.camera.height_px = 48;
    cfg_.camera.fx_px = cfg_.camera.fy_px = 50.0;
    cfg_.camera.cx_px = 32.0;
    cfg_.camera.cy_px = 24.0;
    LiveTrackerSettings s;
    s.camera = PinholeCamera::from_settings(cfg_.camera);
    tracker_.emplace(cfg_, s, LiveTrackerRings{pool_, frames_, imu_, poses_, results_, nullptr});
  }
  LiveStatusSources sources(const PoseQualityCounts* q) {
    return {&task_, nullptr, &*tracker_, nullptr, &frames_, &imu_, &poses_, nullptr, nullptr, q};
  }
  static std::optional<std::uint64_t> fault(const dds::StatusSnapshot& st, const std::string& n) {
    for (std::uint32_t i = 0; i < st.fault_count; ++i) {
      if (n == st.faults[i].name) return st.faults[i].count;
    }
    return std::nullopt;
  }

  config::RobotConfig cfg_;
  rt::FramePool pool_{{.slots = 4, .width = 64, .height = 48, .colour_channels = 3}};
  rt::SpscRing<rt::FrameHandle> frames_{2};
  rt::SpscRing<ImuSample> imu_{16};
  rt::SpscRing<PoseSample> poses_{16};
  rt::SpscRing<LiveFrameResult> results_{16};
  std::optional<LiveTracker> tracker_;
  rt::PeriodicTask task_{rt::thread_spec("tracker"), [] {}};
};

TEST_F(PoseQualityStatus, CountsOfPropagatedDegenerateAndRestartedPosesAreStatusFaults) {
  PoseQualityCounts q;
  q.add(PoseSource::kInitial, kPoseFlagNone);
  q.add(PoseSource::kTracked, kPoseFlagDegenerate);
  q.add(PoseSource::kImuPropagated, kPoseFlagMapRestarted);
  q.add(PoseSource::kImuPropagated, kPoseFlagImuUnavailable);
  const dds::StatusSnapshot st = make_status_snapshot(sources(&q), 1'000);
  EXPECT_EQ(fault(st, "tracker.poses_imu_propagated"), 2u);
  EXPECT_EQ(fault(st, "tracker.poses_degenerate"), 1u);
  EXPECT_EQ(fault(st, "tracker.map_restarts"), 1u);
  EXPECT_EQ(st.tracking_state, dds::TrackingState::kLost);
  // The tracker's own fault counters are still there, and the table has room for them all.
  EXPECT_EQ(fault(st, "tracker.imu_unavailable"), 0u);
  EXPECT_LT(st.fault_count, dds::StatusSnapshot::kMaxFaults);
}

TEST_F(PoseQualityStatus, WithoutCountsNoPoseFaultsAndTheStateFromTheFrameCount) {
  const dds::StatusSnapshot st = make_status_snapshot(sources(nullptr), 1'000);
  EXPECT_FALSE(fault(st, "tracker.poses_imu_propagated"));
  EXPECT_EQ(st.tracking_state, dds::TrackingState::kStarting);
}

}  // namespace
}  // namespace vigs::pipeline
