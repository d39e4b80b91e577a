#include "tracking/loop_closure.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_set>

#include "core/capacity_bytes.hpp"
#include "core/geometry/so3.hpp"
#include "tracking/gaussian_cloud.hpp"

namespace vigs::tracking {
namespace {

/// Drift model of an odometry edge over a translation of d metres: the tracker's relative
/// error per metre of path is 1-3 cm and 0.06-0.08 degrees (RPE per metre, BENCHMARKS.md,
/// Accuracy at the paper's scale), a random walk, so variances grow with d; a floor for a
/// keyframe made by rotation alone.
Matrix6d odometry_information(double d_m) {
  const double var_rot = 1e-6 * d_m + 0.25e-6;  // (1 mrad)^2 per metre, (0.5 mrad)^2 floor
  const double var_pos = 9e-4 * d_m + 1e-5;     // (3 cm)^2 per metre, (3 mm)^2 floor
  Vector6d w;
  w << 1.0 / var_rot, 1.0 / var_rot, 1.0 / var_rot, 1.0 / var_pos, 1.0 / var_pos, 1.0 / var_pos;
  return w.asDiagonal();
}

/// Across a tracker restart nothing is known of the relative pose.
Matrix6d loose_information() {
  return (Vector6d::Constant(1e-6)).asDiagonal();
}

double view_angle_rad(const geometry::Pose& a, const geometry::Pose& b) {
  const double c = a.linear().col(2).dot(b.linear().col(2));
  return std::acos(std::clamp(c, -1.0, 1.0));
}

/// The keyframe's static points thinned to one per voxel of `voxel_m` (the first in the
/// cloud's order), so that a kept cloud's density does not depend on the distance it was seen
/// from. Only what GICP reads (points and regularised covariances, 48 B a point; the raw
/// covariances and colours stay empty). A hash set of voxel keys: allocation is fine off the
/// real-time threads.
void voxel_static_copy(const Keyframe& kf, double voxel_m, GaussianCloud& out) {
  out.clear();
  const GaussianCloud& c = kf.cloud_c;
  const bool flags = kf.moving.size() == c.size();
  const double inv = 1.0 / voxel_m;
  std::unordered_set<std::int64_t> seen;
  seen.reserve(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (flags && kf.moving[i] != 0) continue;
    const Eigen::Vector3f& p = c.points_m[i];
    const auto key = [&](float v) {
      return static_cast<std::int64_t>(std::floor(static_cast<double>(v) * inv)) & 0x1fffff;
    };
    if (!seen.insert(key(p.x()) | (key(p.y()) << 21) | (key(p.z()) << 42)).second) continue;
    out.points_m.push_back(p);
    out.cov_m2.push_back(c.cov_m2[i]);
  }
  out.points_m.shrink_to_fit();  // kept for minutes: hold what is used, and count it exactly
  out.cov_m2.shrink_to_fit();
}

std::size_t cloud_bytes(const GaussianCloud& c) {
  return capacity_bytes(c.points_m, c.cov_m2);
}

constexpr double kAnchorViewRad = M_PI / 6.0;  // views this close see the same place

}  // namespace

LoopCloser::LoopCloser(const Setting& setting, const config::GicpSetting& gicp)
    : setting_(setting), team_(std::max(1, gicp.num_threads), rt::ThreadSpec{.name = "loop_w"}) {
  stages_.reserve(3);
  const double fine = std::max(gicp.max_correspondence_distance_m, 1.5 * setting.cloud_voxel_m);
  for (const double dist : {0.4, 0.2, fine}) {
    config::GicpSetting s = gicp;
    s.max_correspondence_distance_m = std::max(dist, fine);
    stages_.push_back(std::make_unique<Gicp>(s, &team_));
  }
}

const LoopCloser::Anchor* LoopCloser::candidate(std::int64_t t_ns,
                                                const geometry::Pose& T_w_c) const {
  const auto min_age_ns = static_cast<std::int64_t>(setting_.min_age_s * 1e9);
  const double max_angle = setting_.max_view_angle_deg * M_PI / 180.0;
  const Anchor* best = nullptr;
  double best_d = setting_.search_radius_m;
  for (const Anchor& a : anchors_) {
    if (a.t_ns > t_ns - min_age_ns) break;  // anchors are in time order
    const geometry::Pose& T_w_a = graph_.pose(a.node);
    const double d = (T_w_a.translation() - T_w_c.translation()).norm();
    if (d >= best_d || view_angle_rad(T_w_a, T_w_c) > max_angle) continue;
    best = &a;
    best_d = d;
  }
  return best;
}

std::optional<PoseGraphEdge> LoopCloser::verify(const Anchor& anchor, int node,
                                                const GaussianCloud& source_c,
                                                const geometry::Pose& T_w_c) {
  if (anchor.cloud_c.size() < 100 || source_c.size() < 100) return std::nullopt;
  tree_.build(anchor.cloud_c.points_m);
  const CloudTarget target{&anchor.cloud_c, &tree_, nullptr};
  const geometry::Pose T_a_k_guess = graph_.pose(anchor.node).inverse() * T_w_c;
  geometry::Pose T_a_k = T_a_k_guess;
  GicpResult r;
  for (const auto& stage : stages_) {
    r = stage->align(target, source_c, T_a_k);
    if (r.verdict == GicpVerdict::diverged) return std::nullopt;
    T_a_k = r.T_t_s;
  }
  const double moved = (T_a_k.translation() - T_a_k_guess.translation()).norm();
  // A degenerate verdict is kept: the Hessian carries which directions are weak.
  const bool ok = r.verdict != GicpVerdict::diverged && r.information.allFinite() &&
                  r.inlier_ratio >= setting_.min_inlier_ratio && moved < setting_.search_radius_m &&
                  T_a_k.matrix().allFinite();
  if (!ok) return std::nullopt;
  PoseGraphEdge e;
  e.i = anchor.node;
  e.j = node;
  e.T_i_j = T_a_k;
  // GICP's own information, not divided by the tracker's gicp_variance_scale (which weighs
  // GICP against the IMU prior): the directions the two views leave weak (a corridor's axis)
  // stay weak in the graph.
  e.information = information_of_left_increment(r.information, T_a_k);
  return e;
}

bool LoopCloser::add_keyframe(const Keyframe& kf, bool after_restart) {
  ++stats_.keyframes;
  // The newest node's solved pose carries the corrections found so far; the keyframe is
  // placed relative to it by its odometry, so candidates are searched where the corrected
  // trajectory puts it.
  geometry::Pose T_w_c_graph = kf.T_w_c;
  if (!node_estimate_.empty()) {
    const geometry::Pose T_prev_k = node_estimate_.back().inverse() * kf.T_w_c;
    T_w_c_graph = graph_.pose(static_cast<int>(graph_.num_nodes()) - 1) * T_prev_k;
  }
  const int node = graph_.add_node(T_w_c_graph);
  node_t_ns_.push_back(kf.t_ns);
  node_estimate_.push_back(kf.T_w_c);
  node_after_restart_.push_back(node > 0 && after_restart ? 1 : 0);
  if (node > 0) {
    PoseGraphEdge e;
    e.i = node - 1;
    e.j = node;
    e.T_i_j = node_estimate_[static_cast<std::size_t>(node - 1)].inverse() * kf.T_w_c;
    e.information =
        after_restart ? loose_information() : odometry_information(e.T_i_j.translation().norm());
    graph_.add_edge(e);
  }
  GaussianCloud sparse;
  voxel_static_copy(kf, setting_.cloud_voxel_m, sparse);

  bool closed = false;
  if (const Anchor* a = candidate(kf.t_ns, T_w_c_graph)) {
    ++stats_.attempts;
    if (const auto edge = verify(*a, node, sparse, T_w_c_graph)) {
      graph_.add_edge(*edge);
      ++stats_.closures;
      closed = true;
      optimize();
    } else {
      ++stats_.rejected;
    }
  }

  if (new_place(node)) {
    stats_.anchor_bytes += cloud_bytes(sparse);
    anchors_.push_back(Anchor{node, kf.t_ns, std::move(sparse)});
    bound_anchors();
    stats_.anchors = static_cast<std::int64_t>(anchors_.size());
  }
  return closed;
}

bool LoopCloser::new_place(int node) const {
  const geometry::Pose& T_w_c = graph_.pose(node);
  return std::none_of(anchors_.begin(), anchors_.end(), [&](const Anchor& a) {
    const geometry::Pose& T_w_a = graph_.pose(a.node);
    return (T_w_a.translation() - T_w_c.translation()).norm() < setting_.anchor_spacing_m &&
           view_angle_rad(T_w_a, T_w_c) <= kAnchorViewRad;
  });
}

void LoopCloser::bound_anchors() {
  const auto budget = static_cast<std::size_t>(setting_.max_anchor_mb * 1024.0 * 1024.0);
  // O(n^2) per drop over a few hundred anchors: well under a millisecond beside the GICP of a
  // verification, and only once the budget is reached.
  while (stats_.anchor_bytes > budget && anchors_.size() > 1) {
    std::size_t drop = 0;  // the oldest, when no anchor has a neighbour seen the same way
    double drop_d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i + 1 < anchors_.size(); ++i) {  // never the newest
      const geometry::Pose& T_w_i = graph_.pose(anchors_[i].node);
      for (std::size_t j = 0; j < anchors_.size(); ++j) {
        if (j == i) continue;
        const geometry::Pose& T_w_j = graph_.pose(anchors_[j].node);
        const double d = (T_w_i.translation() - T_w_j.translation()).norm();
        if (d < drop_d && view_angle_rad(T_w_i, T_w_j) <= kAnchorViewRad) {
          drop = i;
          drop_d = d;
        }
      }
    }
    stats_.anchor_bytes -= cloud_bytes(anchors_[drop].cloud_c);
    anchors_.erase(anchors_.begin() + static_cast<std::ptrdiff_t>(drop));
    ++stats_.anchors_dropped;
  }
}

const PoseGraphResult& LoopCloser::optimize() {
  if (stats_.closures > 0) stats_.last_optimization = graph_.optimize();
  return stats_.last_optimization;
}

geometry::Pose LoopCloser::raw_correction(std::size_t node) const {
  return graph_.pose(static_cast<int>(node)) * node_estimate_[node].inverse();
}

geometry::Pose LoopCloser::correction(std::size_t node) const {
  if (stats_.closures == 0) return raw_correction(node);
  // The window of keyframes whose solved corrections are smoothed, not across a restart
  // (where the correction jumps for a reason).
  std::size_t first = node > kCorrectionHalfWindow ? node - kCorrectionHalfWindow : 0;
  std::size_t last = std::min(node + kCorrectionHalfWindow, node_estimate_.size() - 1);
  for (std::size_t m = node; m > first; --m) {
    if (node_after_restart_[m]) first = m;
  }
  for (std::size_t m = node + 1; m <= last; ++m) {
    if (node_after_restart_[m]) {
      last = m - 1;
      break;
    }
  }
  // A straight line through the window's corrections (translation, and rotation as a tangent
  // vector at this keyframe's), read at this keyframe: the mean where the window is
  // symmetric, and no lag at the ends of the chain (the newest keyframe) where drift grows
  // along the path.
  const geometry::Pose C_here = raw_correction(node);
  const Eigen::Matrix3d R_here = C_here.linear();
  double s_x = 0.0, s_xx = 0.0;
  Eigen::Matrix<double, 6, 1> s_y = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> s_xy = Eigen::Matrix<double, 6, 1>::Zero();
  for (std::size_t m = first; m <= last; ++m) {
    const geometry::Pose C = raw_correction(m);
    const double x = static_cast<double>(m) - static_cast<double>(node);
    Eigen::Matrix<double, 6, 1> y;
    y << geometry::so3_log<double>(Eigen::Matrix3d(R_here.transpose() * C.linear())),
        C.translation();
    s_x += x;
    s_xx += x * x;
    s_y += y;
    s_xy += x * y;
  }
  const double n = static_cast<double>(last - first + 1);
  const double det = n * s_xx - s_x * s_x;
  // Intercept of the least-squares line; a window of one keyframe is that keyframe's own.
  const Eigen::Matrix<double, 6, 1> y0 =
      det > 0.0 ? ((s_xx * s_y - s_x * s_xy) / det).eval() : (s_y / n).eval();
  geometry::Pose out = geometry::Pose::Identity();
  out.linear() = geometry::normalize_rotation<double>(
      Eigen::Matrix3d(R_here * geometry::so3_exp<double>(Eigen::Vector3d(y0.head<3>()))));
  out.translation() = y0.tail<3>();
  return out;
}

geometry::Pose LoopCloser::solved(std::size_t node) const {
  if (stats_.closures == 0) return graph_.pose(static_cast<int>(node));
  return correction(node) * node_estimate_[node];
}

geometry::Pose LoopCloser::corrected(std::int64_t t_ns, const geometry::Pose& T_w_c) const {
  if (stats_.closures == 0) return T_w_c;  // bit for bit: nothing was measured to correct it
  const auto it = std::upper_bound(node_t_ns_.begin(), node_t_ns_.end(), t_ns);
  if (it == node_t_ns_.begin()) return T_w_c;
  const auto k = static_cast<std::size_t>(it - node_t_ns_.begin()) - 1;
  geometry::Pose C = correction(k);
  if (k + 1 < node_t_ns_.size() && t_ns > node_t_ns_[k]) {
    // Between two keyframes the correction goes from one's to the other's (rotation by slerp,
    // translation linearly), so that no frame steps where the reference keyframe changes.
    const double u = static_cast<double>(t_ns - node_t_ns_[k]) /
                     static_cast<double>(node_t_ns_[k + 1] - node_t_ns_[k]);
    C = geometry::interpolate(C, correction(k + 1), u);
  }
  const geometry::Pose T_w_c_new = C * T_w_c;
  geometry::Pose out = geometry::Pose::Identity();
  out.linear() = geometry::normalize_rotation<double>(Eigen::Matrix3d(T_w_c_new.linear()));
  out.translation() = T_w_c_new.translation();
  return out;
}

}  // namespace vigs::tracking
