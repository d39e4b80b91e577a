#pragma once
// The live tracker task fed in lockstep by a RecordingSource, with the rings and the keyframe
// hand-off it has in vigs run, for tests that drive tick() themselves and play the mapper's,
// the publisher's and the main thread's sides on their own threads.
#include <cstdint>
#include <string>

#include "pipeline/keyframe_handoff.hpp"
#include "pipeline/live_tracker.hpp"
#include "pipeline/recording_source.hpp"

namespace vigs::pipeline::testing {

struct LockstepTrackerRig {
  /// `pool_slots`: as rt.frame_pool_slots (the held keyframes' frames are part of it);
  /// `driver_faults`: LiveTrackerSettings::driver_faults (must outlive the rig).
  LockstepTrackerRig(const config::RobotConfig& cfg, const std::string& path,
                     std::uint32_t pool_slots = 16,
                     const DriverFaultCounts* driver_faults = nullptr)
      : camera(RecordingSource::first_camera(path)),
        pool({.slots = pool_slots,
              .width = static_cast<std::uint32_t>(camera.width_px),
              .height = static_cast<std::uint32_t>(camera.height_px),
              .colour_channels = 3}),
        handoff(2, static_cast<std::size_t>(camera.width_px * camera.height_px)),
        tracker(cfg, tracker_settings(camera, driver_faults),
                {pool, frames, imu, poses, results, &handoff}),
        source(source_settings(path), pool, frames, imu) {
    source.start();
  }

  static LiveTrackerSettings tracker_settings(const PinholeCamera& camera,
                                              const DriverFaultCounts* driver_faults) {
    LiveTrackerSettings ts;
    ts.lockstep = true;
    ts.camera = camera;
    ts.driver_faults = driver_faults;
    return ts;
  }
  static RecordingSourceSettings source_settings(const std::string& path) {
    RecordingSourceSettings rs;
    rs.path = path;
    rs.lockstep = true;
    return rs;
  }

  PinholeCamera camera;
  rt::FramePool pool;
  rt::SpscRing<rt::FrameHandle> frames{4};
  rt::SpscRing<ImuSample> imu{1024};
  rt::SpscRing<PoseSample> poses{256};
  rt::SpscRing<LiveFrameResult> results{1024};
  KeyframeHandoff handoff;
  LiveTracker tracker;
  RecordingSource source;
};

}  // namespace vigs::pipeline::testing
