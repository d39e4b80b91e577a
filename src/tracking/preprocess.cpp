#include "tracking/preprocess.hpp"

namespace vigs::tracking {

FramePreprocessor::FramePreprocessor(const PinholeCamera& camera, const Setting& setting,
                                     rt::WorkerTeam& team)
    : depth_(camera, setting.depth), setting_(setting), team_(&team), fallback_tree_(setting.tree) {
  // Every buffer sized for a whole frame now: a frame with more points than any before it
  // must not allocate on the tracker's thread.
  const std::size_t n = max_points();
  pending_.resize(static_cast<std::size_t>(team.size()));
  for (std::vector<std::uint32_t>& part : pending_) part.reserve(n);
  fallback_points_.reserve(n);
  fallback_tree_.reserve(n);
  grid_.point_at.reserve(n);
  grid_.cell_of.reserve(n);
}

std::size_t FramePreprocessor::max_points() const {
  return depth_.max_points();
}

DepthToPointsStats FramePreprocessor::process(const RgbdView& frame, GaussianCloud& out) {
  const DepthToPointsStats stats = depth_.convert(frame, out, &grid_);
  covariances(out, nullptr);
  return stats;
}

DepthToPointsStats FramePreprocessor::process(const RgbdView& frame, GaussianCloud& out,
                                              KdTree& tree, PixelGrid* grid) {
  const DepthToPointsStats stats = depth_.convert(frame, out, &grid_);
  tree.build(out.points_m, team_);
  covariances(out, &tree);
  if (grid != nullptr) {
    *grid = grid_;  // reuses grid's capacity
  }
  return stats;
}

void FramePreprocessor::covariances(GaussianCloud& out, KdTree* tree) {
  last_fallbacks_ = 0;
  const bool organised =
      setting_.covariance.knn_search == KnnSearch::image_grid && grid_.describes(out.size());
  if (!organised) {
    if (tree == nullptr) {
      fallback_tree_.build(out.points_m, team_);
      tree = &fallback_tree_;
    }
    estimate_covariances(*tree, setting_.covariance, *team_, out);
    return;
  }
  estimate_covariances(grid_, organized_, setting_.covariance, *team_, out, pending_);
  fallback_points_.clear();
  for (const std::vector<std::uint32_t>& part : pending_) {  // team order: deterministic
    fallback_points_.insert(fallback_points_.end(), part.begin(), part.end());
  }
  last_fallbacks_ = fallback_points_.size();
  if (fallback_points_.empty()) {
    return;
  }
  if (tree == nullptr) {
    fallback_tree_.build(out.points_m, team_);  // the team is idle here: both halves at once
    tree = &fallback_tree_;
  }
  estimate_covariances_of(*tree, setting_.covariance, fallback_points_, out);
}

}  // namespace vigs::tracking
