#include "tracking/kdtree.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

namespace vigs::tracking {

// Bounded sorted list of the best candidates so far (insertion sort; k is small).
struct KdTree::Result {
  int k = 0;
  int count = 0;
  std::uint32_t* indices = nullptr;
  float* sq_dists = nullptr;
  float worst = std::numeric_limits<float>::infinity();  ///< pruning bound

  void offer(std::uint32_t index, float d2) {
    if (d2 >= worst) {
      return;
    }
    int i = count < k ? count++ : k - 1;
    while (i > 0 && sq_dists[i - 1] > d2) {
      sq_dists[i] = sq_dists[i - 1];
      indices[i] = indices[i - 1];
      --i;
    }
    sq_dists[i] = d2;
    indices[i] = index;
    if (count == k) {
      worst = sq_dists[k - 1];
    }
  }
};

void KdTree::build(const std::vector<Eigen::Vector3f>& points) {
  const auto n = static_cast<std::uint32_t>(points.size());
  index_.resize(n);
  std::iota(index_.begin(), index_.end(), 0u);
  points_.resize(n);
  slot_of_.resize(n);
  nodes_.clear();
  const std::size_t leaf = static_cast<std::size_t>(std::max(1, setting_.leaf_size));
  nodes_.reserve(2 * (n / leaf + 1) + 1);
  points_ = points;  // sorted in place through index_ below, then gathered
  if (n > 0) {
    build_node(0, n);
  }
  for (std::uint32_t s = 0; s < n; ++s) {
    points_[s] = points[index_[s]];
    slot_of_[index_[s]] = s;
  }
}

std::uint32_t KdTree::build_node(std::uint32_t begin, std::uint32_t end) {
  const auto id = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  if (end - begin <= static_cast<std::uint32_t>(std::max(1, setting_.leaf_size))) {
    nodes_[id].begin = begin;
    nodes_[id].end = end;
    return id;
  }
  Eigen::Array3f lo = Eigen::Array3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Array3f hi = -lo;
  for (std::uint32_t i = begin; i < end; ++i) {
    lo = lo.min(points_[index_[i]].array());
    hi = hi.max(points_[index_[i]].array());
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const std::uint32_t mid = begin + (end - begin) / 2;
  // Ties broken by index so the tree (and every query result) is deterministic.
  std::nth_element(index_.begin() + begin, index_.begin() + mid, index_.begin() + end,
                   [this, axis](std::uint32_t a, std::uint32_t b) {
                     const float pa = points_[a][axis], pb = points_[b][axis];
                     return pa < pb || (pa == pb && a < b);
                   });
  const float split = points_[index_[mid]][axis];
  build_node(begin, mid);
  const std::uint32_t right = build_node(mid, end);
  nodes_[id].axis = axis;
  nodes_[id].split = split;
  nodes_[id].right = right;
  return id;
}

// rd: squared distance from q to the current cell; off[a]: q's offset from the cell along a.
void KdTree::search(std::uint32_t node_id, const Eigen::Vector3f& q, float rd, float* off,
                    Result& result) const {
  const Node& node = nodes_[node_id];
  if (node.axis < 0) {
    for (std::uint32_t s = node.begin; s < node.end; ++s) {
      result.offer(index_[s], (points_[s] - q).squaredNorm());
    }
    return;
  }
  const int a = node.axis;
  const float diff = q[a] - node.split;
  const std::uint32_t near_child = diff < 0.0f ? node_id + 1 : node.right;
  const std::uint32_t far_child = diff < 0.0f ? node.right : node_id + 1;
  search(near_child, q, rd, off, result);
  const float old_off = off[a];
  const float far_rd = rd - old_off * old_off + diff * diff;
  if (far_rd < result.worst) {
    off[a] = diff;
    search(far_child, q, far_rd, off, result);
    off[a] = old_off;
  }
}

int KdTree::knn(const Eigen::Vector3f& q, int k, std::uint32_t* indices, float* sq_dists) const {
  if (nodes_.empty() || k <= 0) {
    return 0;
  }
  Result result;
  result.k = std::min(k, kMaxK);
  result.indices = indices;
  result.sq_dists = sq_dists;
  float off[3] = {0.0f, 0.0f, 0.0f};
  search(0, q, 0.0f, off, result);
  return result.count;
}

bool KdTree::nearest(const Eigen::Vector3f& q, float max_sq_dist, std::uint32_t& index,
                     float& sq_dist) const {
  if (nodes_.empty()) {
    return false;
  }
  Result result;
  result.k = 1;
  result.indices = &index;
  result.sq_dists = &sq_dist;
  result.worst = max_sq_dist;
  float off[3] = {0.0f, 0.0f, 0.0f};
  search(0, q, 0.0f, off, result);
  return result.count == 1;
}

}  // namespace vigs::tracking
