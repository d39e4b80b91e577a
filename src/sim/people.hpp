#pragma once
// Walking people: articulated boxes (torso, head, two swinging legs and arms) that pace up
// and down corridor stretches, off the corridor centre line where the camera travels.
// Positions are a closed-form function of time, so any instant can be rendered.
#include <cstdint>
#include <vector>

#include "sim/bvh.hpp"
#include "sim/hit.hpp"
#include "sim/scene.hpp"

namespace vigs::sim {

/// An oriented box: centre, rotation R_w_p (column-major 3x3: local axes in world), half sizes.
struct PartObb {
  Vec3f center;
  float R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  Vec3f half;
  Material material = Material::kCloth;
  std::uint32_t tint = 0;
};

struct Walker {
  Eigen::Vector2d a, b;  ///< pacing between a and b, metres
  double speed_mps = 1.2;
  double phase_m = 0.0;  ///< distance already walked at t = 0
  std::uint32_t shirt = 0, trousers = 0;
};

/// Everyone's parts at one instant, with a BVH over the people.
class PeopleSnapshot {
 public:
  static constexpr int kPartsPerPerson = 6;

  PeopleSnapshot() = default;
  PeopleSnapshot(const std::vector<Walker>& walkers, double t_s);

  /// Lowers t_best and fills `hit` if the ray meets a person closer than t_best.
  bool intersect(const Ray& ray, float& t_best, Hit& hit) const;
  /// Unsigned distance from p to the nearest part surface (tests).
  [[nodiscard]] float distance_to_surface(Vec3f p) const;
  [[nodiscard]] const std::vector<PartObb>& parts() const { return parts_; }

 private:
  std::vector<PartObb> parts_;
  Bvh bvh_;
};

/// N walkers on the scene's walkways; deterministic for the seed.
std::vector<Walker> make_walkers(const Scene& scene, int count, std::uint64_t seed);

}  // namespace vigs::sim
