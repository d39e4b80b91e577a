#pragma once
// The live pipeline's 1 Hz status (dds::StatusSnapshot) and its drop total, from the stages'
// counters; called on the pipeline's main thread.
#include <cstdint>

#include "core/types/imu_sample.hpp"
#include "core/types/pose_sample.hpp"
#include "dds/status_snapshot.hpp"
#include "drivers/serial_imu/serial_imu_driver.hpp"
#include "pipeline/live_camera.hpp"
#include "pipeline/live_mapper.hpp"
#include "pipeline/live_tracker.hpp"
#include "pipeline/pose_quality.hpp"
#include "rt/frame_pool.hpp"
#include "rt/periodic_task.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::pipeline {

struct LiveStatusSources {
  const rt::PeriodicTask* tracker_task = nullptr;
  const rt::PeriodicTask* mapper_task = nullptr;  ///< null without mapping
  const LiveTracker* tracker = nullptr;
  const LiveMapper* mapper = nullptr;  ///< null without mapping
  const rt::SpscRing<rt::FrameHandle>* frames = nullptr;
  const rt::SpscRing<ImuSample>* imu = nullptr;
  const rt::SpscRing<PoseSample>* poses = nullptr;
  const LiveCamera* camera = nullptr;  ///< the drivers, when they run
  const drivers::SerialImuDriver* imu_driver = nullptr;
  /// The poses' sources and flags (the main thread's count): tracking_state and the
  /// tracker.poses_* faults; null: tracking_state from the frame count alone.
  const PoseQualityCounts* pose_quality = nullptr;
};

/// Drops counted by the tracker (skipped frames, full pose / result rings, keyframes).
std::uint64_t total_drops(const LiveStatusSources& s);

dds::StatusSnapshot make_status_snapshot(const LiveStatusSources& s, std::int64_t now_ns);

}  // namespace vigs::pipeline
