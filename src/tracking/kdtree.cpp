#include "tracking/kdtree.hpp"

#include "tracking/knn_list.hpp"

#include <algorithm>
#include <bit>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace vigs::tracking {

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct NearestResult {
  float worst = kInf;  ///< best distance so far (or the caller's bound)
  std::uint32_t index = 0;
  bool found = false;

  void offer(std::uint32_t i, float d2) {
    if (d2 < worst) {
      worst = d2;
      index = i;
      found = true;
    }
  }
};

}  // namespace

void KdTree::reserve(std::size_t max_points) {
  const std::size_t leaf = static_cast<std::size_t>(std::max(1, setting_.leaf_size));
  // Median splits leave at least half a leaf in each leaf: at most 2n/leaf leaves, so fewer
  // than 4n/leaf + 1 nodes; each leaf pads to kLane.
  const std::size_t nodes = 4 * (max_points / leaf + 1) + 1;
  build_.reserve(max_points);
  points_.reserve(max_points);
  index_.reserve(max_points);
  slot_of_.reserve(max_points);
  leaf_of_slot_.reserve(max_points);
  nodes_.reserve(nodes);
  right_nodes_.reserve(nodes);
  cells_.reserve(nodes);
  const std::size_t padded = max_points + nodes * kLane;
  x_.reserve(padded);
  y_.reserve(padded);
  z_.reserve(padded);
  block_index_.reserve(padded);
}

void KdTree::build(const std::vector<Eigen::Vector3f>& points, rt::WorkerTeam* team) {
  const auto n = static_cast<std::uint32_t>(points.size());
  build_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    build_[i] = BuildPoint{{points[i].x(), points[i].y(), points[i].z()}, i};
  }
  nodes_.clear();
  const std::size_t leaf = static_cast<std::size_t>(std::max(1, setting_.leaf_size));
  nodes_.reserve(2 * (n / leaf + 1) + 1);
  if (n > 0 && (team == nullptr || team->size() < 2 || n < 4096)) {
    build_node(nodes_, 0, n);
  } else if (n > 0) {
    // Root split here, then the two halves in parallel: the left one into nodes_, the
    // right one into right_nodes_ (local ids), appended afterwards with an id offset.
    // Each half touches only its own range of build_, so the tree is the serial one.
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

  // Leaf order for point()/leaf_order(), then the padded SoA blocks. Leaves appear in
  // nodes_ in increasing slot order (pre-order build, right half appended after the left).
  points_.resize(n);
  index_.resize(n);
  slot_of_.resize(n);
  for (std::uint32_t s = 0; s < n; ++s) {
    const BuildPoint& b = build_[s];
    points_[s] = Eigen::Vector3f(b.p[0], b.p[1], b.p[2]);
    index_[s] = b.index;
    slot_of_[b.index] = s;
  }
  std::size_t padded = 0;
  for (const Node& node : nodes_) {
    if (node.axis < 0) {
      padded += (node.end - node.begin + kLane - 1) / kLane * kLane;
    }
  }
  x_.assign(padded, kInf);
  y_.assign(padded, kInf);
  z_.assign(padded, kInf);
  block_index_.assign(padded, 0u);
  std::uint32_t at = 0;
  leaf_of_slot_.resize(n);
  for (Node& node : nodes_) {
    if (node.axis >= 0) {
      continue;
    }
    const std::uint32_t count = node.end - node.begin;
    std::fill(leaf_of_slot_.begin() + node.begin, leaf_of_slot_.begin() + node.end,
              static_cast<std::uint32_t>(&node - nodes_.data()));
    for (std::uint32_t j = 0; j < count; ++j) {
      const BuildPoint& b = build_[node.begin + j];
      x_[at + j] = b.p[0];
      y_[at + j] = b.p[1];
      z_[at + j] = b.p[2];
      block_index_[at + j] = b.index;
    }
    node.begin = at;
    node.end = at + (count + kLane - 1) / kLane * kLane;
    at = node.end;
  }
  cells_.resize(nodes_.size());
  if (n > 0) {
    record_cells(0, Cell{{-kInf, -kInf, -kInf}, {kInf, kInf, kInf}});
  }
}

// A left child holds the points with p[axis] <= split, a right child those >= split.
void KdTree::record_cells(std::uint32_t node_id, Cell cell) {
  const Node& node = nodes_[node_id];
  if (node.axis < 0) {
    cells_[node_id] = cell;
    return;
  }
  Cell left = cell, right = cell;
  left.hi[node.axis] = node.split;
  right.lo[node.axis] = node.split;
  record_cells(node_id + 1, left);
  record_cells(node.right, right);
}

float KdTree::split_range(std::uint32_t begin, std::uint32_t end, std::uint32_t& mid, int& axis) {
  float lo[3] = {kInf, kInf, kInf};
  float hi[3] = {-kInf, -kInf, -kInf};
  for (std::uint32_t i = begin; i < end; ++i) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], build_[i].p[a]);
      hi[a] = std::max(hi[a], build_[i].p[a]);
    }
  }
  axis = 0;
  for (int a = 1; a < 3; ++a) {
    if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
  }
  mid = begin + (end - begin) / 2;
  // Ties broken by index so the tree (and every query result) is deterministic.
  const int a = axis;
  std::nth_element(build_.begin() + begin, build_.begin() + mid, build_.begin() + end,
                   [a](const BuildPoint& l, const BuildPoint& r) {
                     return l.p[a] < r.p[a] || (l.p[a] == r.p[a] && l.index < r.index);
                   });
  return build_[mid].p[axis];
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

// Squared distances of kLane padded points at a time; only those below the current bound
// are offered (the bound may shrink while a group is offered; offer() re-checks).
template <class R>
void KdTree::scan_leaf(const Node& leaf, const float* q, R& result) const {
#if defined(__SSE2__)
  const __m128 qx = _mm_set1_ps(q[0]);
  const __m128 qy = _mm_set1_ps(q[1]);
  const __m128 qz = _mm_set1_ps(q[2]);
  for (std::uint32_t s = leaf.begin; s < leaf.end; s += 4) {
    const __m128 dx = _mm_sub_ps(_mm_loadu_ps(&x_[s]), qx);
    const __m128 dy = _mm_sub_ps(_mm_loadu_ps(&y_[s]), qy);
    const __m128 dz = _mm_sub_ps(_mm_loadu_ps(&z_[s]), qz);
    // Same association as Eigen's squaredNorm(): (x^2 + y^2) + z^2.
    const __m128 d2 =
        _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
    unsigned mask =
        static_cast<unsigned>(_mm_movemask_ps(_mm_cmplt_ps(d2, _mm_set1_ps(result.worst))));
    if (mask != 0u) {
      alignas(16) float d[4];
      _mm_store_ps(d, d2);
      while (mask != 0u) {
        const int j = std::countr_zero(mask);
        result.offer(block_index_[s + static_cast<std::uint32_t>(j)], d[j]);
        mask &= mask - 1u;
      }
    }
  }
#else
  for (std::uint32_t s = leaf.begin; s < leaf.end; ++s) {
    const float dx = x_[s] - q[0], dy = y_[s] - q[1], dz = z_[s] - q[2];
    const float d2 = (dx * dx + dy * dy) + dz * dz;
    if (d2 < result.worst) {
      result.offer(block_index_[s], d2);
    }
  }
#endif
}

// rd: squared distance from q to the current cell; off[a]: q's offset from the cell along a.
template <class R>
void KdTree::search(std::uint32_t node_id, const float* q, float rd, float* off, R& result) const {
  const Node& node = nodes_[node_id];
  if (node.axis < 0) {
    scan_leaf(node, q, result);
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
  KnnList result;
  result.k = std::min(k, kMaxK);
  result.indices = indices;
  result.sq_dists = sq_dists;
  const float qa[3] = {q.x(), q.y(), q.z()};
  float off[3] = {0.0f, 0.0f, 0.0f};
  search(0, qa, 0.0f, off, result);
  return result.count;
}

bool KdTree::nearest(const Eigen::Vector3f& q, float max_sq_dist, std::uint32_t& index,
                     float& sq_dist, std::uint32_t hint) const {
  if (nodes_.empty()) {
    return false;
  }
  NearestResult result;
  result.worst = max_sq_dist;
  const float qa[3] = {q.x(), q.y(), q.z()};
  if (hint < slot_of_.size()) {
    const std::uint32_t leaf = leaf_of_slot_[slot_of_[hint]];
    scan_leaf(nodes_[leaf], qa, result);
    const Cell& c = cells_[leaf];
    float inside = kInf;  // distance from q to the nearest face of the leaf's cell
    for (int a = 0; a < 3; ++a) {
      inside = std::min(inside, std::min(qa[a] - c.lo[a], c.hi[a] - qa[a]));
    }
    if (inside > 0.0f && result.worst <= inside * inside * (1.0f - 1e-5f)) {
      // Every other leaf lies beyond a face: nothing there can beat the bound.
      if (result.found) {
        index = result.index;
        sq_dist = result.worst;
      }
      return result.found;
    }
  }
  float off[3] = {0.0f, 0.0f, 0.0f};
  search(0, qa, 0.0f, off, result);
  if (result.found) {
    index = result.index;
    sq_dist = result.worst;
  }
  return result.found;
}

}  // namespace vigs::tracking
