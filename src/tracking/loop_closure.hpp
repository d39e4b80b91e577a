#pragma once
// Loop closure over the tracker's keyframes: the odometry's drift (about 1 degree of yaw and
// tens of centimetres over a 175 m office loop, BENCHMARKS.md) is bounded where the camera
// comes back to a place it has seen, as every RGB-D SLAM system with a back end does (the
// paper's VIGS has none).
//
// - Every keyframe becomes a node of a pose graph (pose_graph.hpp), joined to the previous one
//   by its odometry: the relative pose of the two estimates, with a drift model of the
//   tracker's per-metre error (loop_closure.cpp). Across a tracker restart the edge is loose.
// - Anchors: a keyframe with no anchor within anchor_spacing_m seen within 30 degrees of its
//   view keeps a sparse copy of its static points (one per cloud_voxel_m voxel of the points
//   the moving test did not flag), in its camera frame. A place walked again adds none.
// - Detection is geometric: the nearest anchor at least min_age_s older, within
//   search_radius_m of the keyframe's estimate and with optical axes within
//   max_view_angle_deg. The drift it must bridge is decimetres, so the estimate is the prior
//   (no appearance-based place recognition).
// - Verification: GICP of the keyframe's sparse points to the anchor's, from the estimates'
//   relative pose, with the correspondence distance shrinking 0.4 -> 0.15 m -> the tracker's;
//   accepted when it converges, is not degenerate, matches min_inlier_ratio of the points and
//   moved the guess less than search_radius_m. The result is a loop edge.
// - optimize() solves the graph. A keyframe's correction (T_kf_opt T_kf_est^-1, applied on the
//   left) is read off a straight line fitted through the solved corrections of the keyframes
//   within kCorrectionHalfWindow of it: the odometry's drift changes slowly along the path,
//   while each loop edge carries its own centimetre of GICP noise (sparse clouds), which the
//   drift model's loose odometry edges let pull its keyframe alone. Unsmoothed, the corrected
//   trajectory of the 3-minute office jumped by up to 2.2 cm from one frame to the next.
//   solved(k) is the keyframe's pose so corrected; the map follows it.
// - corrected(t_ns, T_w_c) moves a pose estimated at t_ns with the correction interpolated in
//   time between the keyframes at or before and after t_ns: each keyframe's part of the map
//   moves with its own correction, and a frame between two sees both parts.
//
// Memory: an anchor keeps about 7,000 points of 48 B (0.3 MB) at 720x480; one a metre of new
// path, so about 50 MB for the 175 m office loop. Bounded by max_anchor_mb: beyond it the
// anchor nearest to another seen the same way is dropped (the oldest of equals; the oldest
// when none has such a neighbour), so a long run thins its places evenly instead of
// forgetting its start.
//
// Not on a real-time thread: add_keyframe() allocates (anchor clouds, the kd-tree) and GICP
// runs on its own team. Lockstep replay calls it in line; the result is deterministic.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "core/config/tracking_components.hpp"
#include "rt/worker_team.hpp"
#include "tracking/gicp.hpp"
#include "tracking/kdtree.hpp"
#include "tracking/pose_graph.hpp"

namespace vigs::tracking {

struct Keyframe;

struct LoopClosureStats {
  std::int64_t keyframes = 0;
  std::int64_t anchors = 0;          ///< kept now
  std::int64_t anchors_dropped = 0;  ///< over max_anchor_mb
  std::size_t anchor_bytes = 0;      ///< heap held by the kept clouds
  std::int64_t attempts = 0;         ///< keyframes with a candidate, registered by GICP
  std::int64_t closures = 0;         ///< verified: loop edges
  std::int64_t rejected = 0;         ///< attempts GICP did not verify
  PoseGraphResult last_optimization;
};

class LoopCloser {
 public:
  using Setting = config::LoopClosureSetting;

  /// `gicp`: the tracker's GICP setting (kernel, thresholds, threads; its correspondence
  /// distance is the last stage of verification).
  LoopCloser(const Setting& setting, const config::GicpSetting& gicp);

  /// A keyframe as the tracker made it (T_w_c is its estimate then; keyframes come in time
  /// order). `after_restart`: the tracker restarted its map since the previous keyframe, so
  /// there is no odometry between them. Returns true when it closed a loop.
  bool add_keyframe(const Keyframe& kf, bool after_restart = false);

  /// Keyframes on either side whose solved corrections are smoothed into one's correction
  /// (about 1.5 m of path at the office's keyframe spacing; the drift it smooths changes over
  /// tens of metres).
  static constexpr std::size_t kCorrectionHalfWindow = 5;

  /// Solves the pose graph with every loop edge so far (no-op without one).
  const PoseGraphResult& optimize();

  /// Where keyframe `node` (add_keyframe order) stands after the corrections: its estimate
  /// moved by its smoothed correction; the graph's own pose while no loop was closed.
  [[nodiscard]] geometry::Pose solved(std::size_t node) const;

  /// A pose the odometry estimated at t_ns, corrected as the keyframes around it were: the
  /// newest at or before t_ns and the next, interpolated in time (the newest's alone after the
  /// last keyframe); unchanged (bit for bit) before the first keyframe and while no loop was
  /// closed.
  [[nodiscard]] geometry::Pose corrected(std::int64_t t_ns, const geometry::Pose& T_w_c) const;

  [[nodiscard]] const LoopClosureStats& stats() const { return stats_; }
  [[nodiscard]] const PoseGraph& graph() const { return graph_; }

 private:
  struct Anchor {
    int node = 0;
    std::int64_t t_ns = 0;
    GaussianCloud cloud_c;
  };
  [[nodiscard]] const Anchor* candidate(std::int64_t t_ns, const geometry::Pose& T_w_c) const;
  /// No anchor within anchor_spacing_m of the node seen within 30 degrees of its view.
  [[nodiscard]] bool new_place(int node) const;
  /// The graph's solved pose of `node` times the inverse of its tracked estimate, unsmoothed.
  [[nodiscard]] geometry::Pose raw_correction(std::size_t node) const;
  /// A node's correction, applied on the left: T_opt T_est^-1 smoothed over the window.
  [[nodiscard]] geometry::Pose correction(std::size_t node) const;
  /// Drops the most redundant anchors while the kept clouds exceed max_anchor_mb.
  void bound_anchors();
  /// Registers `source_c` (at T_w_c) to the anchor; the loop edge when verified.
  std::optional<PoseGraphEdge> verify(const Anchor& anchor, int node, const GaussianCloud& source_c,
                                      const geometry::Pose& T_w_c);

  Setting setting_;
  rt::WorkerTeam team_;
  /// Verification stages, correspondence distance 0.4 m, 0.15 m, then the tracker's.
  std::vector<std::unique_ptr<Gicp>> stages_;
  KdTree tree_;
  PoseGraph graph_;
  std::vector<std::int64_t> node_t_ns_;
  std::vector<geometry::Pose> node_estimate_;  ///< the tracker's poses (graph_ holds the solved)
  std::vector<char> node_after_restart_;       ///< its odometry edge is loose (tracker restart)
  std::vector<Anchor> anchors_;
  LoopClosureStats stats_;
};

}  // namespace vigs::tracking
