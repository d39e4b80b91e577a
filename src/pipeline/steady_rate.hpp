#pragma once
// The real-time factor in steady state: sensor time covered over wall time between two frames
// inside the run, so that neither start-up (the first poses wait for the IMU, the local map is
// empty) nor the drain at the end (the last frames are tracked while nothing new arrives)
// enters it. A pipeline that keeps up has 1.0 there however long it started; one that falls
// behind has the ratio of the camera's rate to its own. The whole run's factor (stream time over
// wall time from the first frame) stays beside it.
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace vigs::pipeline {

/// Frames in pose order: `stream_ns` their sensor stamps, `done_ns` when their poses were pushed
/// (CLOCK_MONOTONIC). Takes the frames at the `trim` and 1 - `trim` fractions of the run (trim
/// in [0, 0.5)) and returns (stream_ns[b] - stream_ns[a]) / (done_ns[b] - done_ns[a]); nothing
/// with fewer than 3 frames, unequal lengths or a wall span that is not positive.
std::optional<double> steady_real_time_factor(const std::vector<std::int64_t>& stream_ns,
                                              const std::vector<std::int64_t>& done_ns,
                                              double trim = 0.1);

/// How many of `event_ns` (CLOCK_MONOTONIC) fall between the poses of the same two frames
/// steady_real_time_factor() measures between (`done_ns` in pose order, same `trim`): e.g. the
/// tracker's overruns in steady state. Nothing with fewer than 3 frames.
std::optional<std::uint64_t> events_in_steady_window(const std::vector<std::int64_t>& done_ns,
                                                     std::span<const std::int64_t> event_ns,
                                                     double trim = 0.1);

}  // namespace vigs::pipeline
