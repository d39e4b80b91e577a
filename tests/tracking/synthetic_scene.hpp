#pragma once
// Deterministic synthetic point sets for the tracking tests.
#include <Eigen/Core>
#include <random>
#include <vector>

namespace vigs::tracking::test {

/// A room corner seen from the origin: floor, two walls, a box and a ball, about n points
/// spread over 1-4 m in front of the camera (z forward).
inline std::vector<Eigen::Vector3f> room_scene(int n, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Eigen::Vector3f> pts;
  pts.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const float a = u(rng), b = u(rng);
    switch (i % 5) {
      case 0:  // floor y = 1.2 (y down)
        pts.emplace_back(-2.0f + 4.0f * a, 1.2f, 1.0f + 3.0f * b);
        break;
      case 1:  // back wall z = 4
        pts.emplace_back(-2.0f + 4.0f * a, -1.0f + 2.2f * b, 4.0f);
        break;
      case 2:  // side wall x = -2
        pts.emplace_back(-2.0f, -1.0f + 2.2f * a, 1.0f + 3.0f * b);
        break;
      case 3: {  // box 0.6 m on the floor: top and two faces
        const int face = static_cast<int>(u(rng) * 3.0f);
        if (face == 0) {
          pts.emplace_back(0.3f + 0.6f * a, 0.6f, 2.0f + 0.6f * b);
        } else if (face == 1) {
          pts.emplace_back(0.3f + 0.6f * a, 0.6f + 0.6f * b, 2.0f);
        } else {
          pts.emplace_back(0.3f, 0.6f + 0.6f * a, 2.0f + 0.6f * b);
        }
        break;
      }
      default: {  // ball r = 0.3 at (-0.8, 0.5, 2.5)
        const float th = 2.0f * 3.14159265f * a, z = 2.0f * b - 1.0f;
        const float s = std::sqrt(1.0f - z * z);
        pts.emplace_back(-0.8f + 0.3f * s * std::cos(th), 0.5f + 0.3f * z,
                         2.5f + 0.3f * s * std::sin(th));
        break;
      }
    }
  }
  return pts;
}

/// n points on the plane z = 2 (x, y in [-2, 2]).
inline std::vector<Eigen::Vector3f> plane_scene(int n, unsigned seed = 3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < n; ++i) {
    pts.emplace_back(u(rng), u(rng), 2.0f);
  }
  return pts;
}

}  // namespace vigs::tracking::test
