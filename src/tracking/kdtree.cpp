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

void KdTree::build(const std::vector<Eigen::Vector3f>& points, ForkJoin* team) {
  const auto n = static_cast<std::uint32_t>(points.size());
  index_.resize(n);
  std::iota(index_.begin(), index_.end(), 0u);
  slot_of_.resize(n);
  nodes_.clear();
  const std::size_t leaf = static_cast<std::size_t>(std::max(1, setting_.leaf_size));
  nodes_.reserve(2 * (n / leaf + 1) + 1);
  points_ = points;  // read through index_ while building, then gathered into leaf order
  if (n > 0 && (team == nullptr || team->size() < 2 || n < 4096)) {
    build_node(nodes_, 0, n);
  } else if (n > 0) {
    // Root split here, then the two halves in parallel: the left one into nodes_, the
    // right one into right_nodes_ (local ids), appended afterwards with an id offset.
    // Each half touches only its own range of index_, so the tree is the serial one.
    std::uint32_t mid = 0;
    int axis = 0;
    const float split = split_range(0, n, mid, axis);
    nodes_.emplace_back();
    right_nodes_.clear();
    right_nodes_.reserve(nodes_.capacity());
    team->run([&](int t) {
      if (t == 0) build_node(nodes_, 0, mid);
      if (t == 1) build_node(right_nodes_, mid, n);
    });
    const auto offset = static_cast<std::uint32_t>(nodes_.size());
    for (Node node : right_nodes_) {
      if (node.axis >= 0) node.right += offset;
      nodes_.push_back(node);
    }
    nodes_[0].axis = axis;
    nodes_[0].split = split;
    nodes_[0].right = offset;
  }
  for (std::uint32_t s = 0; s < n; ++s) {
    points_[s] = points[index_[s]];
    slot_of_[index_[s]] = s;
  }
}

float KdTree::split_range(std::uint32_t begin, std::uint32_t end, std::uint32_t& mid, int& axis) {
  Eigen::Array3f lo = Eigen::Array3f::Constant(std::numeric_limits<float>::infinity());
  Eigen::Array3f hi = -lo;
  for (std::uint32_t i = begin; i < end; ++i) {
    lo = lo.min(points_[index_[i]].array());
    hi = hi.max(points_[index_[i]].array());
  }
  axis = 0;
  (hi - lo).maxCoeff(&axis);
  mid = begin + (end - begin) / 2;
  // Ties broken by index so the tree (and every query result) is deterministic.
  const int a = axis;
  std::nth_element(index_.begin() + begin, index_.begin() + mid, index_.begin() + end,
                   [this, a](std::uint32_t l, std::uint32_t r) {
                     const float pl = points_[l][a], pr = points_[r][a];
                     return pl < pr || (pl == pr && l < r);
                   });
  return points_[index_[mid]][axis];
}

std::uint32_t KdTree::build_node(std::vector<Node>& nodes, std::uint32_t begin, std::uint32_t end) {
  const auto id = static_cast<std::uint32_t>(nodes.size());
  nodes.emplace_back();
  if (end - begin <= static_cast<std::uint32_t>(std::max(1, setting_.leaf_size))) {
    nodes[id].begin = begin;
    nodes[id].end = end;
    return id;
  }
  std::uint32_t mid = 0;
  int axis = 0;
  const float split = split_range(begin, end, mid, axis);
  build_node(nodes, begin, mid);
  const std::uint32_t right = build_node(nodes, mid, end);
  nodes[id].axis = axis;
  nodes[id].split = split;
  nodes[id].right = right;
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
