#pragma once
#include <cstdint>

#include "sim/ray.hpp"
#include "sim/scene.hpp"

namespace vigs::sim {

/// Closest surface hit of a camera ray: distance, outward unit normal, surface and its
/// texture coordinates.
struct Hit {
  float t = 0.0f;
  Vec3f normal;
  Material material = Material::kWall;
  std::uint32_t tint = 0;
  float u = 0.0f, v = 0.0f;
  bool dynamic = false;  ///< a person (moves between frames)
};

}  // namespace vigs::sim
