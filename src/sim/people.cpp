#include "sim/people.hpp"

#include <algorithm>
#include <cmath>

#include "sim/rng.hpp"

namespace vigs::sim {
namespace {

constexpr double kStrideM = 1.3;  ///< distance per full gait cycle

Vec3f rotate(const float R[9], Vec3f v) {
  return {R[0] * v.x + R[3] * v.y + R[6] * v.z, R[1] * v.x + R[4] * v.y + R[7] * v.z,
          R[2] * v.x + R[5] * v.y + R[8] * v.z};
}
Vec3f rotate_t(const float R[9], Vec3f v) {
  return {R[0] * v.x + R[1] * v.y + R[2] * v.z, R[3] * v.x + R[4] * v.y + R[5] * v.z,
          R[6] * v.x + R[7] * v.y + R[8] * v.z};
}

/// R = Rz(yaw) * Ry(pitch), column-major.
void rot_zy(float yaw, float pitch, float R[9]) {
  const float cz = std::cos(yaw), sz = std::sin(yaw), cy = std::cos(pitch), sy = std::sin(pitch);
  // columns: Rz*Ry*e_x, Rz*Ry*e_y, Rz*Ry*e_z
  R[0] = cz * cy, R[1] = sz * cy, R[2] = -sy;
  R[3] = -sz, R[4] = cz, R[5] = 0.0f;
  R[6] = cz * sy, R[7] = sz * sy, R[8] = cy;
}

}  // namespace

std::vector<Walker> make_walkers(const Scene& scene, int count, std::uint64_t seed) {
  std::vector<Walker> out;
  if (scene.walkways.empty()) return out;
  Rng rng(seed, 0xBEE0);
  for (int i = 0; i < count; ++i) {
    const Walkway& w = scene.walkways[rng.next_u64() % scene.walkways.size()];
    const Eigen::Vector2d dir = (w.b - w.a).normalized();
    const Eigen::Vector2d left(-dir.y(), dir.x());
    // Off the centre line (where the camera is: at least 0.5 m, so that swinging arms stay
    // 0.2 m clear of it), clear of the wall pilasters (0.12 m deep) where the corridor is wide
    // enough, and away from the junctions.
    const double side = (rng.uniform() < 0.5 ? -1.0 : 1.0) * std::max(0.5, w.half_width_m - 0.45);
    Walker k;
    k.a = w.a + dir * 1.6 + left * side;
    k.b = w.b - dir * 1.6 + left * side;
    k.speed_mps = rng.uniform(0.8, 1.4);
    k.phase_m = rng.uniform(0.0, 2.0 * (k.b - k.a).norm());
    k.shirt = static_cast<std::uint32_t>(rng.next_u64());
    k.trousers = static_cast<std::uint32_t>(rng.next_u64());
    out.push_back(k);
  }
  return out;
}

PeopleSnapshot::PeopleSnapshot(const std::vector<Walker>& walkers, double t_s) {
  std::vector<Aabb> boxes;
  parts_.reserve(walkers.size() * kPartsPerPerson);
  for (const Walker& w : walkers) {
    const double len = (w.b - w.a).norm();
    const double walked = w.speed_mps * t_s + w.phase_m;
    const double s = std::fmod(walked, 2.0 * len);
    const Eigen::Vector2d dir = (w.b - w.a) / len;
    const Eigen::Vector2d pos =
        s < len ? Eigen::Vector2d(w.a + dir * s) : Eigen::Vector2d(w.b - dir * (s - len));
    const Eigen::Vector2d heading = s < len ? dir : Eigen::Vector2d(-dir);
    const auto yaw = static_cast<float>(std::atan2(heading.y(), heading.x()));
    const auto swing = static_cast<float>(std::sin(2.0 * M_PI * walked / kStrideM));
    const Vec3f base{static_cast<float>(pos.x()), static_cast<float>(pos.y()), 0.0f};

    auto add = [&](Vec3f pivot, Vec3f offset, float pitch, Vec3f half, Material m,
                   std::uint32_t tint) {
      PartObb p;
      rot_zy(yaw, pitch, p.R);
      float Rz[9];
      rot_zy(yaw, 0.0f, Rz);
      p.center = base + rotate(Rz, pivot) + rotate(p.R, offset);
      p.half = half;
      p.material = m;
      p.tint = tint;
      parts_.push_back(p);
    };
    add({0, 0, 1.15f}, {0, 0, 0}, 0.0f, {0.11f, 0.19f, 0.28f}, Material::kCloth, w.shirt);
    add({0, 0, 1.6f}, {0, 0, 0}, 0.0f, {0.09f, 0.08f, 0.11f}, Material::kSkin, w.shirt);
    for (int side = -1; side <= 1; side += 2) {
      const float sgn = static_cast<float>(side);
      add({0, 0.1f * sgn, 0.87f}, {0, 0, -0.43f}, 0.35f * swing * sgn, {0.07f, 0.07f, 0.43f},
          Material::kCloth, w.trousers);
      add({0, 0.25f * sgn, 1.4f}, {0, 0, -0.3f}, -0.3f * swing * sgn, {0.045f, 0.045f, 0.3f},
          Material::kCloth, w.shirt);
    }
    Aabb box;
    box.lo = base - Vec3f{0.6f, 0.6f, 0.0f};
    box.hi = base + Vec3f{0.6f, 0.6f, 1.75f};
    boxes.push_back(box);
  }
  bvh_ = Bvh(boxes, 2);
}

bool PeopleSnapshot::intersect(const Ray& ray, float& t_best, Hit& hit) const {
  int best = -1;
  int best_axis = 0;
  bool best_neg = false;
  Vec3f best_local;
  bvh_.closest_hit(ray, t_best, [&](std::uint32_t person, float& t) {
    for (int k = 0; k < kPartsPerPerson; ++k) {
      const PartObb& p = parts_[person * kPartsPerPerson + static_cast<std::uint32_t>(k)];
      const Vec3f o = rotate_t(p.R, ray.o - p.center);
      const Vec3f d = rotate_t(p.R, ray.d);
      float t0 = 0.0f, t1 = t;
      int axis = -1;
      bool neg = false;
      for (int i = 0; i < 3; ++i) {
        const float inv = 1.0f / (std::abs(d[i]) < 1e-12f ? 1e-12f : d[i]);
        float a = (-p.half[i] - o[i]) * inv, c = (p.half[i] - o[i]) * inv;
        const bool flipped = a > c;
        if (flipped) std::swap(a, c);
        if (a > t0) {
          t0 = a;
          axis = i;
          neg = !flipped;  // entered through the -half face when not flipped
        }
        t1 = std::min(t1, c);
      }
      if (axis >= 0 && t0 <= t1 && t0 < t) {
        t = t0;
        best = static_cast<int>(person) * kPartsPerPerson + k;
        best_axis = axis;
        best_neg = neg;
        best_local = o + d * t0;
      }
    }
  });
  if (best < 0) return false;
  const PartObb& p = parts_[static_cast<std::size_t>(best)];
  Vec3f n_local{0, 0, 0};
  n_local[best_axis] = best_neg ? -1.0f : 1.0f;
  hit.t = t_best;
  hit.normal = rotate(p.R, n_local);
  hit.material = p.material;
  hit.tint = p.tint;
  hit.u = best_local[(best_axis + 1) % 3];
  hit.v = best_local[(best_axis + 2) % 3];
  hit.dynamic = true;
  return true;
}

float PeopleSnapshot::distance_to_surface(Vec3f pw) const {
  float best = std::numeric_limits<float>::max();
  for (const PartObb& p : parts_) {
    const Vec3f q = rotate_t(p.R, pw - p.center);
    float outside = 0.0f, inside = -std::numeric_limits<float>::max();
    for (int i = 0; i < 3; ++i) {
      const float d = std::abs(q[i]) - p.half[i];
      outside += d > 0 ? d * d : 0.0f;
      inside = std::max(inside, d);
    }
    const float dist = outside > 0 ? std::sqrt(outside) : -inside;
    best = std::min(best, dist);
  }
  return best;
}

}  // namespace vigs::sim
