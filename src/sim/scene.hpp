#pragma once
// The static world: axis-aligned boxes (walls, door lintels, furniture) between a floor plane
// at z = 0 and a ceiling plane, plus the corridor graph that the camera route and the walking
// people follow. World frame: z up, metres.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "sim/ray.hpp"

namespace vigs::sim {

/// Surface kinds; each has its own procedural texture (sim/texture.hpp).
enum class Material : std::uint8_t {
  kFloor,
  kCeiling,
  kWall,
  kWood,
  kMetal,
  kFabric,
  kScreen,
  kSkin,
  kCloth,
};

struct SceneBox {
  Aabb box;
  Material material = Material::kWall;
  std::uint32_t tint = 0;  ///< per-object colour seed
};

/// A straight stretch of corridor centreline (for people); metres in the floor plane.
struct Walkway {
  Eigen::Vector2d a, b;
  double half_width_m = 1.2;
};

struct Scene {
  std::string name;
  double size_x_m = 0.0, size_y_m = 0.0;
  float ceiling_z_m = 3.0f;
  std::vector<SceneBox> boxes;
  std::vector<Walkway> walkways;
  /// Camera route through corridor junctions (no U-turns), metres; revisits junctions.
  std::vector<Eigen::Vector2d> route;
};

}  // namespace vigs::sim
