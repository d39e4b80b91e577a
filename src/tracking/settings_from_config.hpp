#pragma once
// The robot file's `tracking:` section (core/config/tracking_settings.hpp) binds the tracking
// components' settings directly (core/config/tracking_components.hpp): cfg.tracking.gicp is
// a Gicp::Setting, cfg.tracking.preprocess a FramePreprocessor::Setting. The tracker adds its
// threads.
#include "core/config/tracking_settings.hpp"
#include "tracking/tracker.hpp"

namespace vigs::tracking {

/// The tracker's setting from the robot file: its components' parts as they are, and one team
/// of `num_threads` for preprocessing and GICP.
inline Tracker::Setting tracker_setting(const config::TrackingSettings& c) {
  Tracker::Setting s;
  static_cast<config::TrackerSetting&>(s) = c;
  s.preprocess_threads = c.gicp.num_threads;
  return s;
}

}  // namespace vigs::tracking
