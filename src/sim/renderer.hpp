#pragma once
// CPU ray caster: one ray per pixel through the pinhole model, closest hit among the floor
// and ceiling planes, the static boxes (BVH) and the people (per-frame BVH), procedural
// albedo with fixed directional shading. Depth is z in the camera frame (the ray direction
// has unit camera z), with a sensor model: noise sigma = base + quadratic * z^2, holes at
// grazing incidence, limited range. Rows are shared out among threads; noise comes from a
// counter-based hash of (seed, pixel), so the image does not depend on the thread count.
#include <cstdint>
#include <vector>

#include "core/geometry/se3.hpp"
#include "core/types/pinhole_camera.hpp"
#include "sim/bvh.hpp"
#include "sim/hit.hpp"
#include "sim/people.hpp"
#include "sim/scene.hpp"

namespace vigs::sim {

struct RenderSettings {
  float min_depth_m = 0.1f;
  float max_depth_m = 10.0f;
  float depth_noise_base_m = 0.0005f;
  float depth_noise_quadratic_per_m = 0.0015f;  ///< sigma grows with z^2
  float hole_cos = 0.12f;        ///< incidence cosine below which depth is always missing
  float dropout_cos = 0.25f;     ///< between hole_cos and this, missing with rising probability
  float rgb_noise_sigma = 1.0f;  ///< 8-bit grey levels
  bool noise = true;             ///< false: exact depth and colour (holes and range still apply)
  bool gray = false;             ///< mono8 instead of rgb8
  int threads = 2;
};

struct RgbdFrame {
  int width = 0, height = 0;
  bool gray = false;
  std::vector<std::uint8_t> color;  ///< rgb8 or mono8, row-major
  std::vector<float> depth_m;       ///< 0 = no measurement
  /// 255 where a person is the closest surface, 0 elsewhere (ground truth, row-major), set
  /// whether or not the depth pixel is valid: the map leaves people out by design, so the
  /// evaluation measures it on the other pixels.
  std::vector<std::uint8_t> dynamic_mask;
};

class Renderer {
 public:
  Renderer(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings);

  /// Renders the view from T_w_c (camera: x right, y down, z forward). `noise_key` selects
  /// the noise pattern (e.g. a hash of the seed and frame index).
  void render(const geometry::Pose& T_w_c, const PeopleSnapshot& people, std::uint64_t noise_key,
              RgbdFrame& out) const;

  /// Closest hit of a world ray with direction of any length; false if nothing is hit.
  bool cast(const Ray& ray, const PeopleSnapshot* people, Hit& hit) const;

  /// Unsigned distance from p to the nearest static surface (boxes, floor, ceiling); tests.
  [[nodiscard]] float distance_to_static_surface(Vec3f p) const;

  [[nodiscard]] const Bvh& bvh() const { return bvh_; }
  [[nodiscard]] const RenderSettings& settings() const { return s_; }
  [[nodiscard]] const PinholeCamera& camera() const { return cam_; }

 private:
  void render_rows(const geometry::Pose& T_w_c, const PeopleSnapshot& people,
                   std::uint64_t noise_key, int row0, int row1, RgbdFrame& out) const;

  const Scene& scene_;
  PinholeCamera cam_;
  RenderSettings s_;
  Bvh bvh_;
};

}  // namespace vigs::sim
