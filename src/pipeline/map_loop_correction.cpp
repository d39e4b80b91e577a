#include "pipeline/map_loop_correction.hpp"

#include <stdexcept>

namespace vigs::pipeline {

geometry::Pose MapLoopCorrection::place(const tracking::LoopCloser& loops) {
  if (loops.graph().num_nodes() == 0)
    throw std::invalid_argument("MapLoopCorrection::place: the loop closer has no keyframe");
  const std::size_t k = loops.graph().num_nodes() - 1;
  const geometry::Pose T_w_c = loops.solved(k);
  if (placed_.size() <= k) {
    placed_.resize(k + 1, geometry::Pose::Identity());
    is_placed_.resize(k + 1, 0);
  }
  placed_[k] = T_w_c;
  is_placed_[k] = 1;
  return T_w_c;
}

std::size_t MapLoopCorrection::apply(const tracking::LoopCloser& loops, mapping::Mapper& mapper) {
  corrections_.clear();
  const std::size_t n = std::min(placed_.size(), loops.graph().num_nodes());
  for (std::size_t k = 0; k < n; ++k) {
    if (!is_placed_[k]) continue;
    const geometry::Pose T_new = loops.solved(k);
    const geometry::Pose T_new_old = T_new * placed_[k].inverse();
    const double turn = Eigen::AngleAxisd(T_new_old.linear()).angle();
    if (T_new_old.translation().norm() < kMinMoveM && turn < kMinTurnRad) continue;
    corrections_.push_back({k, T_new_old});
    placed_[k] = T_new;
  }
  mapper.move_keyframes(corrections_);
  return corrections_.size();
}

}  // namespace vigs::pipeline
