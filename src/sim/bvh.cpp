#include "sim/bvh.hpp"

#include <algorithm>
#include <array>
#include <numeric>

namespace vigs::sim {

Bvh::Bvh(const std::vector<Aabb>& prim_boxes, int max_leaf) {
  if (prim_boxes.empty()) return;
  order_.resize(prim_boxes.size());
  std::iota(order_.begin(), order_.end(), 0u);
  std::vector<Vec3f> centers(prim_boxes.size());
  for (std::size_t i = 0; i < prim_boxes.size(); ++i) centers[i] = prim_boxes[i].center();
  nodes_.reserve(2 * prim_boxes.size());
  nodes_.emplace_back();
  build(0, 0, static_cast<std::uint32_t>(prim_boxes.size()), 1, prim_boxes, centers, max_leaf);
}

void Bvh::build(std::uint32_t node, std::uint32_t first, std::uint32_t count, int level,
                const std::vector<Aabb>& boxes, const std::vector<Vec3f>& centers, int max_leaf) {
  depth_ = std::max(depth_, level);
  Aabb box, cbox;
  for (std::uint32_t i = first; i < first + count; ++i) {
    box.grow(boxes[order_[i]]);
    cbox.grow(centers[order_[i]]);
  }
  nodes_[node].box = box;
  const auto make_leaf = [&] {
    nodes_[node].first = first;
    nodes_[node].count = count;
  };
  if (count <= 1) return make_leaf();

  // Binned SAH over the centroid extent, every axis.
  constexpr int kBins = 16;
  float best_cost = std::numeric_limits<float>::max();
  int best_axis = -1, best_split = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = cbox.lo[axis], hi = cbox.hi[axis];
    if (hi - lo < 1e-6f) continue;
    std::array<Aabb, kBins> bin_box{};
    std::array<int, kBins> bin_count{};
    const float scale = kBins / (hi - lo);
    for (std::uint32_t i = first; i < first + count; ++i) {
      int b = static_cast<int>((centers[order_[i]][axis] - lo) * scale);
      b = std::clamp(b, 0, kBins - 1);
      bin_box[b].grow(boxes[order_[i]]);
      ++bin_count[b];
    }
    std::array<float, kBins> right_area{};
    std::array<int, kBins> right_count{};
    Aabb acc;
    int n = 0;
    for (int b = kBins - 1; b > 0; --b) {
      acc.grow(bin_box[b]);
      n += bin_count[b];
      right_area[b] = acc.area();
      right_count[b] = n;
    }
    acc = Aabb{};
    n = 0;
    for (int b = 0; b < kBins - 1; ++b) {
      acc.grow(bin_box[b]);
      n += bin_count[b];
      if (n == 0 || right_count[b + 1] == 0) continue;
      const float cost = acc.area() * n + right_area[b + 1] * right_count[b + 1];
      if (cost < best_cost) {
        best_cost = cost;
        best_axis = axis;
        best_split = b + 1;
      }
    }
  }
  const float leaf_cost = box.area() * count;
  if (best_axis < 0 || (count <= static_cast<std::uint32_t>(max_leaf) && best_cost >= leaf_cost)) {
    if (best_axis >= 0 || count <= static_cast<std::uint32_t>(max_leaf)) return make_leaf();
  }
  std::uint32_t mid;
  if (best_axis < 0) {
    mid = first + count / 2;  // coincident centroids: split the list in half
  } else {
    const float lo = cbox.lo[best_axis];
    const float scale = kBins / (cbox.hi[best_axis] - lo);
    const auto it = std::partition(order_.begin() + first, order_.begin() + first + count,
                                   [&](std::uint32_t p) {
                                     int b = static_cast<int>((centers[p][best_axis] - lo) * scale);
                                     return std::clamp(b, 0, kBins - 1) < best_split;
                                   });
    mid = static_cast<std::uint32_t>(it - order_.begin());
    if (mid == first || mid == first + count) mid = first + count / 2;
  }
  const auto left = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  nodes_.emplace_back();
  nodes_[node].first = left;
  nodes_[node].count = 0;
  build(left, first, mid - first, level + 1, boxes, centers, max_leaf);
  build(left + 1, mid, first + count - mid, level + 1, boxes, centers, max_leaf);
}

}  // namespace vigs::sim
