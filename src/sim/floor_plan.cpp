#include "sim/floor_plan.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sim/rng.hpp"

namespace vigs::sim {
namespace {

struct Interval {
  double lo, hi;
  bool lo_is_corridor, hi_is_corridor;
};

std::vector<Interval> block_intervals(const FloorPlanParams& p) {
  std::vector<Interval> out;
  double prev = 0.0;
  bool prev_corridor = false;
  for (double c : p.corridor_centers_m) {
    const double hi = c - 0.5 * p.corridor_width_m;
    if (hi - prev > 1.5) out.push_back({prev, hi, prev_corridor, true});
    prev = c + 0.5 * p.corridor_width_m;
    prev_corridor = true;
  }
  if (p.size_m - prev > 1.5) out.push_back({prev, p.size_m, prev_corridor, false});
  return out;
}

/// Cut [a, b] into pieces of roughly [min, max] metres.
std::vector<double> cuts(double a, double b, double min_w, double max_w, Rng& rng) {
  const double len = b - a;
  const int n = std::max(1, static_cast<int>(std::lround(len / (0.5 * (min_w + max_w)))));
  std::vector<double> c{a};
  for (int k = 1; k < n; ++k) {
    c.push_back(a + len * k / n + rng.uniform(-0.2, 0.2) * len / n);
  }
  c.push_back(b);
  return c;
}

Aabb make_box(double x0, double y0, double z0, double x1, double y1, double z1) {
  Aabb b;
  b.lo = {static_cast<float>(std::min(x0, x1)), static_cast<float>(std::min(y0, y1)),
          static_cast<float>(std::min(z0, z1))};
  b.hi = {static_cast<float>(std::max(x0, x1)), static_cast<float>(std::max(y0, y1)),
          static_cast<float>(std::max(z0, z1))};
  return b;
}

enum Side { kSouth = 0, kNorth = 1, kWest = 2, kEast = 3 };

struct Rect {
  double x0, y0, x1, y1;
  [[nodiscard]] bool overlaps(const Rect& o) const {
    return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1;
  }
};

class Builder {
 public:
  Builder(const FloorPlanParams& p, Scene& s, Rng& rng) : p_(p), s_(s), rng_(rng) {}

  void add(const Aabb& b, Material m) {
    s_.boxes.push_back({b, m, static_cast<std::uint32_t>(rng_.next_u64())});
  }

  /// The block whose rooms come next (to know which room sides face a corridor).
  void set_block(const Interval& x, const Interval& y) {
    bx_ = x;
    by_ = y;
  }

  /// A room's own four walls inside its rectangle, a door on `door_side`, pilasters on the
  /// corridor side of walls that face a corridor, and furniture.
  void room(const Rect& r, Side door_side) {
    const double t = p_.wall_thickness_m, H = p_.wall_height_m;
    const std::uint32_t tint = static_cast<std::uint32_t>(rng_.next_u64());
    auto wall = [&](const Aabb& b) { s_.boxes.push_back({b, Material::kWall, tint}); };
    double door_u = 0.0;
    // Each side: (along-axis start, end) and the fixed band across.
    for (int side = 0; side < 4; ++side) {
      const bool horizontal = side == kSouth || side == kNorth;
      const double a0 = horizontal ? r.x0 : r.y0 + t;
      const double a1 = horizontal ? r.x1 : r.y1 - t;
      const double c0 = side == kSouth   ? r.y0
                        : side == kNorth ? r.y1 - t
                        : side == kWest  ? r.x0
                                         : r.x1 - t;
      const double c1 = c0 + t;
      auto seg = [&](double u0, double u1, double z0, double z1) {
        if (u1 - u0 < 1e-3) return;
        wall(horizontal ? make_box(u0, c0, z0, u1, c1, z1) : make_box(c0, u0, z0, c1, u1, z1));
      };
      if (side != door_side) {
        seg(a0, a1, 0.0, H);
        continue;
      }
      const double dw = p_.door_width_m;
      const double u = rng_.uniform(a0 + 0.4, std::max(a0 + 0.4, a1 - 0.4 - dw));
      door_u = u;
      seg(a0, u, 0.0, H);
      seg(u + dw, a1, 0.0, H);
      seg(u, u + dw, p_.door_height_m, H);
      // Keep the floor in front of the door (inside the room) clear of furniture.
      const double depth = 1.3;
      if (horizontal) {
        const double y0 = side == kSouth ? r.y0 : r.y1 - depth;
        occupied_.push_back({u - 0.2, y0, u + dw + 0.2, y0 + depth});
      } else {
        const double x0 = side == kWest ? r.x0 : r.x1 - depth;
        occupied_.push_back({x0, u - 0.2, x0 + depth, u + dw + 0.2});
      }
    }
    pilasters(r, door_side, door_u);
    furnish({r.x0 + t, r.y0 + t, r.x1 - t, r.y1 - t}, door_side);
    occupied_.clear();
  }

 private:
  struct Item {
    double length, depth, height;
    Material material;
  };

  /// Shallow full-height pilasters (0.3 m wide, 0.12 m deep) every 2.5-4.5 m on the corridor
  /// face of the room's corridor-facing walls: geometry along otherwise flat corridors, so that
  /// depth-only registration is constrained along the corridor axis.
  void pilasters(const Rect& r, Side door_side, double door_u) {
    constexpr double kWidth = 0.3, kDepth = 0.12;
    const bool faces[4] = {std::abs(r.y0 - by_.lo) < 1e-9 && by_.lo_is_corridor,
                           std::abs(r.y1 - by_.hi) < 1e-9 && by_.hi_is_corridor,
                           std::abs(r.x0 - bx_.lo) < 1e-9 && bx_.lo_is_corridor,
                           std::abs(r.x1 - bx_.hi) < 1e-9 && bx_.hi_is_corridor};
    const std::uint32_t tint = static_cast<std::uint32_t>(rng_.next_u64());
    for (int side = 0; side < 4; ++side) {
      if (!faces[side]) continue;
      const bool horizontal = side == kSouth || side == kNorth;
      const double a0 = horizontal ? r.x0 : r.y0, a1 = horizontal ? r.x1 : r.y1;
      const double c0 = side == kSouth   ? r.y0 - kDepth
                        : side == kNorth ? r.y1
                        : side == kWest  ? r.x0 - kDepth
                                         : r.x1;
      for (double a = a0 + rng_.uniform(0.3, 1.5); a + kWidth < a1 - 0.1;
           a += rng_.uniform(2.5, 4.5)) {
        if (side == door_side && a + kWidth > door_u - 0.35 &&
            a < door_u + p_.door_width_m + 0.35) {
          continue;
        }
        const Aabb b = horizontal ? make_box(a, c0, 0.0, a + kWidth, c0 + kDepth, p_.wall_height_m)
                                  : make_box(c0, a, 0.0, c0 + kDepth, a + kWidth, p_.wall_height_m);
        s_.boxes.push_back({b, Material::kWall, tint});
      }
    }
  }

  void furnish(const Rect& in, Side door_side) {
    static const Item kItems[] = {{1.4, 0.7, 0.75, Material::kWood},    // desk
                                  {1.0, 0.45, 1.9, Material::kMetal},   // cabinet
                                  {0.9, 0.35, 2.0, Material::kWood},    // bookshelf
                                  {0.5, 0.5, 0.46, Material::kFabric},  // chair seat
                                  {1.8, 0.8, 0.8, Material::kFabric}};  // sofa
    const int n = rng_.uniform_int(2, 5);
    for (int k = 0; k < n; ++k) {
      const Item& it = kItems[rng_.uniform_int(0, 4)];
      for (int attempt = 0; attempt < 12; ++attempt) {
        int side = rng_.uniform_int(0, 3);
        if (side == door_side) side = (side + 1) % 4;
        const bool horizontal = side == kSouth || side == kNorth;
        const double span = horizontal ? in.x1 - in.x0 : in.y1 - in.y0;
        if (span < it.length + 0.2) continue;
        const double u = rng_.uniform(0.1, span - it.length - 0.1);
        Rect rr;
        if (horizontal) {
          const double y0 = side == kSouth ? in.y0 : in.y1 - it.depth;
          rr = {in.x0 + u, y0, in.x0 + u + it.length, y0 + it.depth};
        } else {
          const double x0 = side == kWest ? in.x0 : in.x1 - it.depth;
          rr = {x0, in.y0 + u, x0 + it.depth, in.y0 + u + it.length};
        }
        if (std::any_of(occupied_.begin(), occupied_.end(),
                        [&](const Rect& o) { return o.overlaps(rr); })) {
          continue;
        }
        occupied_.push_back(rr);
        add(make_box(rr.x0, rr.y0, 0.0, rr.x1, rr.y1, it.height), it.material);
        if (it.material == Material::kWood && it.height < 1.0) {  // a monitor on the desk
          const double cx = 0.5 * (rr.x0 + rr.x1), cy = 0.5 * (rr.y0 + rr.y1);
          const double hx = horizontal ? 0.28 : 0.03, hy = horizontal ? 0.03 : 0.28;
          add(make_box(cx - hx, cy - hy, it.height, cx + hx, cy + hy, it.height + 0.38),
              Material::kScreen);
        }
        break;
      }
    }
  }

  const FloorPlanParams& p_;
  Scene& s_;
  Rng& rng_;
  std::vector<Rect> occupied_;
  Interval bx_{}, by_{};
};

void make_route(const FloorPlanParams& p, Scene& s, Rng& rng) {
  const auto& c = p.corridor_centers_m;
  const int n = static_cast<int>(c.size());
  auto at = [&](int i, int j) { return Eigen::Vector2d(c[i], c[j]); };
  // First a loop around the block between junctions (0,0) and (1,1): a revisit early on.
  std::vector<std::pair<int, int>> nodes = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}};
  double length = 4.0 * (c[1] - c[0]);
  while (length < p.route_length_m) {
    const auto [i, j] = nodes.back();
    const auto [pi, pj] = nodes[nodes.size() - 2];
    std::vector<std::pair<int, int>> next;
    for (const auto& [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
      const int ni = i + di, nj = j + dj;
      if (ni < 0 || nj < 0 || ni >= n || nj >= n || (ni == pi && nj == pj)) continue;
      next.push_back({ni, nj});
    }
    const auto pick = next[static_cast<std::size_t>(rng.uniform_int(0, int(next.size()) - 1))];
    length += (at(pick.first, pick.second) - at(i, j)).norm();
    nodes.push_back(pick);
  }
  for (const auto& [i, j] : nodes) s.route.push_back(at(i, j));
  // People walk on every corridor stretch between neighbouring junctions.
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if (i + 1 < n) s.walkways.push_back({at(i, j), at(i + 1, j), 0.5 * p.corridor_width_m});
      if (j + 1 < n) s.walkways.push_back({at(i, j), at(i, j + 1), 0.5 * p.corridor_width_m});
    }
  }
}

}  // namespace

FloorPlanParams office_params() {
  return {};
}

FloorPlanParams apartment_params() {
  FloorPlanParams p;
  p.name = "apartment";
  p.size_m = 24.0;
  p.corridor_centers_m = {4.0, 12.0, 20.0};
  p.corridor_width_m = 1.6;
  p.wall_height_m = 2.6;
  p.room_min_m = 2.8;
  p.room_max_m = 4.5;
  p.split_block_above_m = 6.0;
  p.door_width_m = 0.9;
  p.door_height_m = 2.05;
  p.route_length_m = 150.0;
  return p;
}

Scene generate_floor_plan(const FloorPlanParams& p, std::uint64_t seed) {
  if (p.corridor_centers_m.size() < 2) throw std::invalid_argument("need >= 2 corridors");
  Scene s;
  s.name = p.name;
  s.size_x_m = s.size_y_m = p.size_m;
  s.ceiling_z_m = static_cast<float>(p.wall_height_m);
  Rng rng(seed, 0x5CE7E);
  Builder b(p, s, rng);
  const double L = p.size_m, H = p.wall_height_m;
  // Outer walls, just outside the floor.
  b.add(make_box(-0.3, -0.3, 0, 0, L + 0.3, H), Material::kWall);
  b.add(make_box(L, -0.3, 0, L + 0.3, L + 0.3, H), Material::kWall);
  b.add(make_box(0, -0.3, 0, L, 0, H), Material::kWall);
  b.add(make_box(0, L, 0, L, L + 0.3, H), Material::kWall);

  const auto iv = block_intervals(p);
  for (const auto& X : iv) {
    for (const auto& Y : iv) {
      const double w = X.hi - X.lo, d = Y.hi - Y.lo;
      const bool ycorr = Y.lo_is_corridor && Y.hi_is_corridor;
      const bool xcorr = X.lo_is_corridor && X.hi_is_corridor;
      const bool thin_x = w < p.split_block_above_m, thin_y = d < p.split_block_above_m;
      b.set_block(X, Y);
      if (thin_x && !thin_y) {  // a strip along y: one column, door on a corridor side
        const Side door = X.hi_is_corridor   ? kEast
                          : X.lo_is_corridor ? kWest
                          : Y.lo_is_corridor ? kSouth
                                             : kNorth;
        const auto c = cuts(Y.lo, Y.hi, p.room_min_m, p.room_max_m, rng);
        for (std::size_t k = 0; k + 1 < c.size(); ++k) b.room({X.lo, c[k], X.hi, c[k + 1]}, door);
      } else if (thin_y) {  // a strip along x (or a small corner block): one row
        const Side door = Y.hi_is_corridor   ? kNorth
                          : Y.lo_is_corridor ? kSouth
                          : X.lo_is_corridor ? kWest
                                             : kEast;
        const auto c = cuts(X.lo, X.hi, p.room_min_m, p.room_max_m, rng);
        for (std::size_t k = 0; k + 1 < c.size(); ++k) b.room({c[k], Y.lo, c[k + 1], Y.hi}, door);
      } else if (ycorr || !xcorr) {  // two rows of rooms, doors south / north
        const double mid = 0.5 * (Y.lo + Y.hi);
        for (int row = 0; row < 2; ++row) {
          const auto c = cuts(X.lo, X.hi, p.room_min_m, p.room_max_m, rng);
          for (std::size_t k = 0; k + 1 < c.size(); ++k) {
            b.room(row == 0 ? Rect{c[k], Y.lo, c[k + 1], mid} : Rect{c[k], mid, c[k + 1], Y.hi},
                   row == 0 ? kSouth : kNorth);
          }
        }
      } else {  // two columns, doors west / east
        const double mid = 0.5 * (X.lo + X.hi);
        for (int col = 0; col < 2; ++col) {
          const auto c = cuts(Y.lo, Y.hi, p.room_min_m, p.room_max_m, rng);
          for (std::size_t k = 0; k + 1 < c.size(); ++k) {
            b.room(col == 0 ? Rect{X.lo, c[k], mid, c[k + 1]} : Rect{mid, c[k], X.hi, c[k + 1]},
                   col == 0 ? kWest : kEast);
          }
        }
      }
    }
  }
  make_route(p, s, rng);
  return s;
}

Scene make_preset(const std::string& preset, std::uint64_t seed) {
  if (preset == "office") return generate_floor_plan(office_params(), seed);
  if (preset == "apartment") return generate_floor_plan(apartment_params(), seed);
  throw std::invalid_argument("unknown preset '" + preset + "' (office | apartment)");
}

}  // namespace vigs::sim
