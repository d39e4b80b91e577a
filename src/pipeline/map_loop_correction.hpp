#pragma once
// Keeps the Gaussian map on the loop closer's solved trajectory (tracking.loop_closure), for the
// live mapper and the lockstep replay alike. A keyframe is placed in the map at its solved
// pose (LoopCloser::solved: its odometry pose carried by the corrections found so far), and
// this remembers where each keyframe's part of the map stands. After a closure re-solved the
// graph, apply() moves every keyframe whose solved pose moved since by the difference
// (mapping::Mapper::move_keyframes). The map and trajectory.tum (the corrected poses) then
// share one frame, and a place walked again is inserted where it was first seen instead of
// where the odometry's drift put it. Mapper ids must be the closer's node indices: each
// keyframe goes to both, in the same order.
#include <cstdint>
#include <vector>

#include "core/geometry/se3.hpp"
#include "mapping/mapper.hpp"
#include "tracking/loop_closure.hpp"

namespace vigs::pipeline {

class MapLoopCorrection {
 public:
  /// Corrections smaller than these (a third of a pixel at 2 m at 720x480, where the graph
  /// moves most keyframes of a long run a little at every closure) are left to accumulate:
  /// moving two million Gaussians and rebuilding the insertion occupancy per closure held the
  /// live mapper long enough to drop keyframes at its queue.
  static constexpr double kMinMoveM = 2e-3, kMinTurnRad = 3.5e-4;

  /// The pose at which to insert the keyframe that just became the newest node of `loops`
  /// (LoopCloser::add_keyframe was called for it); remembered as placed there.
  geometry::Pose place(const tracking::LoopCloser& loops);

  /// Moves the map's keyframes whose solved pose moved since they were placed or last moved.
  /// Returns the keyframes moved.
  std::size_t apply(const tracking::LoopCloser& loops, mapping::Mapper& mapper);

 private:
  std::vector<geometry::Pose> placed_;  ///< by node: where its Gaussians stand now
  std::vector<char> is_placed_;         ///< by node: it went to the map (place() was called)
  std::vector<mapping::KeyframeCorrection> corrections_;
};

}  // namespace vigs::pipeline
