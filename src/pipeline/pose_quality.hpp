#pragma once
// The quality of a tracked frame's pose as its subscribers see it: PoseSample::source, the
// PoseFlags the frame itself carries, and the live pipeline's running counts of both for the
// 1 Hz status (faults tracker.poses_imu_propagated, tracker.poses_degenerate,
// tracker.map_restarts, and tracking_state from the newest pose). On DDS the source and flags
// go out with every pose on <prefix>/pose_quality (src/dds/msg/PoseQuality.msg).
#include <cstdint>

#include "core/types/pose_sample.hpp"
#include "dds/status_snapshot.hpp"
#include "pipeline/odometry.hpp"

namespace vigs::pipeline {

/// The first frame starts the map (kInitial); a pose from GICP is kTracked; any other pose (a
/// lost frame, the frame the local map restarted at) is the tracker's guess, kImuPropagated.
inline PoseSource pose_source(const TrackedFrame& f, std::uint64_t index) noexcept {
  if (index == 0) return PoseSource::kInitial;
  return f.pose_from_gicp ? PoseSource::kTracked : PoseSource::kImuPropagated;
}

/// The flags a tracked frame carries by itself: kPoseFlagDegenerate (GICP alone had a weak
/// direction), kPoseFlagMapRestarted (tracking.reinit_after_lost_frames restarted the local map
/// here). The tracker adds the stream's own: frames skipped, out of order, IMU unavailable.
inline std::uint32_t frame_pose_flags(const TrackedFrame& f) noexcept {
  return (f.degenerate ? kPoseFlagDegenerate : 0u) | (f.reinitialized ? kPoseFlagMapRestarted : 0u);
}

/// Counts of the poses a pipeline produced, by source and flag (main thread: from the results
/// it drains, so a result dropped at a full result ring is not counted).
struct PoseQualityCounts {
  std::uint64_t poses = 0;
  std::uint64_t imu_propagated = 0;  ///< source kImuPropagated: tracking lost on the frame
  std::uint64_t degenerate = 0;      ///< kPoseFlagDegenerate
  std::uint64_t map_restarts = 0;    ///< kPoseFlagMapRestarted
  PoseSource last_source = PoseSource::kInitial;
  std::uint32_t last_flags = kPoseFlagNone;

  void add(PoseSource source, std::uint32_t flags) noexcept {
    ++poses;
    imu_propagated += source == PoseSource::kImuPropagated;
    degenerate += (flags & kPoseFlagDegenerate) != 0;
    map_restarts += (flags & kPoseFlagMapRestarted) != 0;
    last_source = source;
    last_flags = flags;
  }
};

/// Status.tracking_state from the newest pose: starting before any; IMU only when it was
/// propagated; lost when it was propagated without an IMU prediction (kPoseFlagImuUnavailable);
/// tracking otherwise.
inline dds::TrackingState tracking_state(const PoseQualityCounts& c) noexcept {
  if (c.poses == 0) return dds::TrackingState::kStarting;
  if (c.last_source != PoseSource::kImuPropagated) return dds::TrackingState::kTracking;
  return (c.last_flags & kPoseFlagImuUnavailable) != 0 ? dds::TrackingState::kLost
                                                       : dds::TrackingState::kImuOnly;
}

}  // namespace vigs::pipeline
