#pragma once
// Bounding volume hierarchy over axis-aligned boxes, built with binned SAH. Primitives are
// referred to by index; the caller's callback decides what a primitive is (an exact box for the
// static scene, a person's articulated parts for people) and does the exact intersection.
#include <cstdint>
#include <vector>

#include "sim/ray.hpp"

namespace vigs::sim {

class Bvh {
 public:
  struct Node {
    Aabb box;
    std::uint32_t first = 0;  ///< leaf: first index into prim_order(); inner: left child
    std::uint32_t count = 0;  ///< leaf: primitive count (> 0); inner: 0 (right = left + 1)
  };

  Bvh() = default;
  /// Builds over `prim_boxes`; leaves hold at most `max_leaf` primitives.
  explicit Bvh(const std::vector<Aabb>& prim_boxes, int max_leaf = 4);

  /// Visits, nearest first, every leaf primitive whose box the ray enters before `t_best`.
  /// `test(prim, t_best)` intersects primitive `prim` and lowers t_best on a closer hit.
  template <class Test>
  void closest_hit(const Ray& ray, float& t_best, Test&& test) const {
    if (nodes_.empty()) return;
    std::uint32_t stack[64];
    int sp = 0;
    if (ray_box_entry(ray, nodes_[0].box, 0.0f, t_best) == kInf) return;
    std::uint32_t node = 0;
    for (;;) {
      const Node& n = nodes_[node];
      if (n.count > 0) {
        for (std::uint32_t i = 0; i < n.count; ++i) test(order_[n.first + i], t_best);
      } else {
        const std::uint32_t l = n.first, r = n.first + 1;
        const float tl = ray_box_entry(ray, nodes_[l].box, 0.0f, t_best);
        const float tr = ray_box_entry(ray, nodes_[r].box, 0.0f, t_best);
        if (tl != kInf && tr != kInf) {
          const bool left_first = tl <= tr;
          stack[sp++] = left_first ? r : l;
          node = left_first ? l : r;
          continue;
        }
        if (tl != kInf) {
          node = l;
          continue;
        }
        if (tr != kInf) {
          node = r;
          continue;
        }
      }
      // Pop, skipping subtrees that now lie beyond the best hit.
      for (;;) {
        if (sp == 0) return;
        node = stack[--sp];
        if (ray_box_entry(ray, nodes_[node].box, 0.0f, t_best) != kInf) break;
      }
    }
  }

  [[nodiscard]] const std::vector<Node>& nodes() const { return nodes_; }
  [[nodiscard]] const std::vector<std::uint32_t>& prim_order() const { return order_; }
  [[nodiscard]] int depth() const { return depth_; }

 private:
  static constexpr float kInf = std::numeric_limits<float>::infinity();
  void build(std::uint32_t node, std::uint32_t first, std::uint32_t count, int level,
             const std::vector<Aabb>& boxes, const std::vector<Vec3f>& centers, int max_leaf);

  std::vector<Node> nodes_;
  std::vector<std::uint32_t> order_;
  int depth_ = 0;
};

}  // namespace vigs::sim
