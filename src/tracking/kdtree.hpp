#pragma once
// A static 3-D kd-tree over float points, written for this project: median split on the
// widest axis, leaves of a few points, and the incremental distance-to-cell bound (Arya &
// Mount) for pruning. Leaves are stored twice: as points in leaf order (point(), leaf_order())
// and as structure-of-arrays blocks padded to a multiple of kLane with points at infinity, so
// a leaf is scanned kLane distances at a time (SSE2 on x86-64, plain loops elsewhere) and only
// candidates closer than the current bound reach the sorted result list. build() reuses its
// buffers, so a tree rebuilt every frame stops allocating once it has seen its largest cloud.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/config/tracking_components.hpp"
#include "rt/worker_team.hpp"

namespace vigs::tracking {

class KdTree {
 public:
  using Setting = config::KdTreeSetting;
  static constexpr int kMaxK = 64;
  static constexpr std::uint32_t kLane = 4;  ///< leaf blocks are padded to a multiple of this

  KdTree() = default;
  explicit KdTree(const Setting& setting) : setting_(setting) {}

  /// Indexes a copy of `points` (finite; the caller may change them afterwards). With a
  /// team of 2+ threads the two halves below the root are built in parallel; the tree is
  /// the same either way.
  void build(const std::vector<Eigen::Vector3f>& points, rt::WorkerTeam* team = nullptr);
  /// Sizes every buffer for up to `max_points` points, so that build() of no more points does
  /// not allocate (real-time callers reserve at start-up).
  void reserve(std::size_t max_points);

  /// The k (<= kMaxK) nearest points to q, nearest first: original indices and squared
  /// distances (m^2). Returns how many were found (< k only when the tree is smaller). Ties
  /// in distance keep the point met first, so results are deterministic.
  int knn(const Eigen::Vector3f& q, int k, std::uint32_t* indices, float* sq_dists) const;

  static constexpr std::uint32_t kNoHint = 0xffffffffu;

  /// Nearest point strictly within sqrt(max_sq_dist); false when there is none. `hint`, an
  /// original index (e.g. the answer for a nearby query), starts the search in the hint's
  /// leaf: when q lies inside that leaf's cell farther from its faces than the best distance
  /// found there, no other leaf can hold a closer point and the descent is skipped. The
  /// nearest distance is the same with or without a hint.
  bool nearest(const Eigen::Vector3f& q, float max_sq_dist, std::uint32_t& index, float& sq_dist,
               std::uint32_t hint = kNoHint) const;

  [[nodiscard]] std::size_t size() const { return index_.size(); }
  /// Original indices in leaf order: querying points in this order keeps the tree's nodes
  /// warm in cache from one query to the next.
  [[nodiscard]] const std::vector<std::uint32_t>& leaf_order() const { return index_; }
  /// Point i in the caller's original order.
  [[nodiscard]] const Eigen::Vector3f& point(std::uint32_t i) const { return points_[slot_of_[i]]; }

 private:
  struct Node {
    float split = 0.0f;
    std::uint32_t begin = 0, end = 0;  ///< leaf: padded range in the SoA blocks
    std::uint32_t right = 0;           ///< inner: right child (left child is this + 1)
    std::int32_t axis = -1;            ///< -1 for a leaf
  };
  /// A point while building: coordinates next to the original index, so partitioning
  /// moves 16 contiguous bytes instead of chasing an index into the point array.
  struct BuildPoint {
    float p[3];
    std::uint32_t index;
  };
  std::uint32_t build_node(std::vector<Node>& nodes, std::uint32_t begin, std::uint32_t end);
  float split_range(std::uint32_t begin, std::uint32_t end, std::uint32_t& mid, int& axis);
  template <class R>
  void search(std::uint32_t node, const float* q, float rd, float* off, R& result) const;
  template <class R>
  void scan_leaf(const Node& leaf, const float* q, R& result) const;

  Setting setting_;
  std::vector<BuildPoint> build_;           ///< partitioned in place while building
  std::vector<Eigen::Vector3f> points_;     ///< leaf order
  std::vector<std::uint32_t> index_;        ///< slot -> original index
  std::vector<std::uint32_t> slot_of_;      ///< original index -> slot
  std::vector<float> x_, y_, z_;            ///< padded SoA leaf blocks
  std::vector<std::uint32_t> block_index_;  ///< padded slot -> original index
  std::vector<Node> nodes_;
  std::vector<Node> right_nodes_;  ///< scratch of the parallel build
  struct Cell {
    float lo[3], hi[3];  ///< the region of space a leaf owns (infinite at the outer faces)
  };
  std::vector<std::uint32_t> leaf_of_slot_;  ///< slot -> node id of its leaf
  std::vector<Cell> cells_;                  ///< node id -> cell (filled for leaves)
  void record_cells(std::uint32_t node, Cell cell);
};

}  // namespace vigs::tracking
