#pragma once
// Procedural surface textures: tiles, grout, paint with low- and high-frequency noise,
// posters, wood grain, screens. Anchored to surface coordinates, so a surface point has the
// same colour from every view (photometric losses and SSIM compare like with like).
#include <cstdint>

#include "sim/scene.hpp"

namespace vigs::sim {

struct Rgb {
  float r = 0, g = 0, b = 0;
};

/// Value noise in [0, 1] on a unit lattice, smooth (C1) between lattice points.
float value_noise(float x, float y, std::uint32_t seed);

/// Albedo in [0, 1] of `material` at surface coordinates (u, v), metres. Walls and
/// furniture sides use u = horizontal coordinate along the face, v = height. `footprint_m`
/// is the size of the pixel on the surface; fine detail fades out where it would alias.
Rgb albedo(Material material, std::uint32_t tint, float u, float v, float footprint_m = 0.0f);

}  // namespace vigs::sim
