#include "sim/renderer.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

#include "sim/rng.hpp"
#include "sim/texture.hpp"

namespace vigs::sim {
namespace {

std::vector<Aabb> boxes_of(const Scene& s) {
  std::vector<Aabb> b;
  b.reserve(s.boxes.size());
  for (const auto& x : s.boxes) b.push_back(x.box);
  return b;
}

inline std::uint8_t to_u8(float v) {
  return static_cast<std::uint8_t>(std::clamp(v, 0.0f, 255.0f) + 0.5f);  // 255.5 -> 255
}

}  // namespace

Renderer::Renderer(const Scene& scene, const PinholeCamera& camera, const RenderSettings& settings)
    : scene_(scene), cam_(camera), s_(settings), bvh_(boxes_of(scene), 4) {}

bool Renderer::cast(const Ray& ray, const PeopleSnapshot* people, Hit& hit) const {
  float t_best = std::numeric_limits<float>::infinity();
  // Floor (z = 0) and ceiling planes first: they bound the BVH search.
  int plane = 0;
  if (ray.d.z < 0.0f) {
    t_best = -ray.o.z / ray.d.z;
    plane = -1;
  } else if (ray.d.z > 0.0f) {
    t_best = (scene_.ceiling_z_m - ray.o.z) / ray.d.z;
    plane = 1;
  }
  std::int64_t best = -1;
  const auto& boxes = scene_.boxes;
  bvh_.closest_hit(ray, t_best, [&](std::uint32_t prim, float& t) {
    const float e = ray_box_entry(ray, boxes[prim].box, 0.0f, t);
    if (e < t) {
      t = e;
      best = prim;
    }
  });
  if (people != nullptr && people->intersect(ray, t_best, hit)) return true;
  if (best >= 0) {
    const SceneBox& b = boxes[static_cast<std::size_t>(best)];
    const Vec3f p = ray.o + ray.d * t_best;
    int axis = 0;
    bool neg = true;
    float dmin = std::numeric_limits<float>::max();
    for (int i = 0; i < 3; ++i) {
      const float dl = std::abs(p[i] - b.box.lo[i]), dh = std::abs(p[i] - b.box.hi[i]);
      if (dl < dmin) dmin = dl, axis = i, neg = true;
      if (dh < dmin) dmin = dh, axis = i, neg = false;
    }
    hit.t = t_best;
    hit.normal = {0, 0, 0};
    hit.normal[axis] = neg ? -1.0f : 1.0f;
    hit.material = b.material;
    hit.tint = b.tint;
    hit.u = axis == 0 ? p.y : p.x;
    hit.v = axis == 2 ? p.y : p.z;
    hit.dynamic = false;
    return true;
  }
  if (plane == 0) return false;
  const Vec3f p = ray.o + ray.d * t_best;
  hit.t = t_best;
  hit.normal = {0, 0, plane < 0 ? 1.0f : -1.0f};
  hit.material = plane < 0 ? Material::kFloor : Material::kCeiling;
  hit.tint = 0;
  hit.u = p.x;
  hit.v = p.y;
  hit.dynamic = false;
  return true;
}

void Renderer::render(const geometry::Pose& T_w_c, const PeopleSnapshot& people,
                      std::uint64_t noise_key, RgbdFrame& out) const {
  out.width = cam_.width_px;
  out.height = cam_.height_px;
  out.gray = s_.gray;
  const std::size_t n = static_cast<std::size_t>(out.width) * out.height;
  out.color.resize(n * (s_.gray ? 1 : 3));
  out.depth_m.resize(n);
  out.dynamic_mask.resize(n);
  constexpr int kRowsPerTask = 8;
  std::atomic<int> next_row{0};
  auto work = [&] {
    for (;;) {
      const int r0 = next_row.fetch_add(kRowsPerTask);
      if (r0 >= out.height) return;
      render_rows(T_w_c, people, noise_key, r0, std::min(out.height, r0 + kRowsPerTask), out);
    }
  };
  std::vector<std::thread> helpers;
  for (int i = 1; i < std::max(1, s_.threads); ++i) helpers.emplace_back(work);
  work();
  for (auto& t : helpers) t.join();
}

void Renderer::render_rows(const geometry::Pose& T_w_c, const PeopleSnapshot& people,
                           std::uint64_t noise_key, int row0, int row1, RgbdFrame& out) const {
  const Eigen::Matrix3f R = T_w_c.linear().cast<float>();
  const Vec3f o{static_cast<float>(T_w_c.translation().x()),
                static_cast<float>(T_w_c.translation().y()),
                static_cast<float>(T_w_c.translation().z())};
  const Vec3f light{0.32f, 0.52f, 0.79f};
  const auto fx = static_cast<float>(cam_.fx_px), fy = static_cast<float>(cam_.fy_px);
  const auto cx = static_cast<float>(cam_.cx_px), cy = static_cast<float>(cam_.cy_px);
  for (int v = row0; v < row1; ++v) {
    const float yc = (static_cast<float>(v) - cy) / fy;
    for (int u = 0; u < out.width; ++u) {
      const float xc = (static_cast<float>(u) - cx) / fx;
      const Vec3f d{R(0, 0) * xc + R(0, 1) * yc + R(0, 2), R(1, 0) * xc + R(1, 1) * yc + R(1, 2),
                    R(2, 0) * xc + R(2, 1) * yc + R(2, 2)};
      const Ray ray = Ray::make(o, d);
      const std::size_t idx = static_cast<std::size_t>(v) * out.width + u;
      Hit hit;
      float depth = 0.0f;
      Rgb c{0.0f, 0.0f, 0.0f};
      const bool hit_any = cast(ray, &people, hit);
      out.dynamic_mask[idx] = hit_any && hit.dynamic ? 255 : 0;
      if (hit_any) {
        const float z = hit.t;  // camera z of d is 1
        const float shade = 0.55f + 0.45f * std::abs(dot(hit.normal, light));
        const float cos_inc = std::abs(dot(hit.normal, d)) / std::sqrt(dot(d, d));
        // Pixel size on the surface, stretched at oblique incidence.
        const float footprint = z / fx / std::max(cos_inc, 0.15f);
        const Rgb a = albedo(hit.material, hit.tint, hit.u, hit.v, footprint);
        c = {a.r * shade, a.g * shade, a.b * shade};
        const std::uint64_t h = hash3(noise_key, idx, 0);
        bool valid = z >= s_.min_depth_m && z <= s_.max_depth_m && cos_inc >= s_.hole_cos;
        if (valid && cos_inc < s_.dropout_cos) {
          const float p_drop = (s_.dropout_cos - cos_inc) / (s_.dropout_cos - s_.hole_cos);
          valid = to_unit(h) >= p_drop;
        }
        if (valid) {
          depth = z;
          if (s_.noise) {
            const float sigma = s_.depth_noise_base_m + s_.depth_noise_quadratic_per_m * z * z;
            depth += sigma * fast_normal_from(mix64(h));
            if (depth < s_.min_depth_m || depth > s_.max_depth_m) depth = 0.0f;
          }
        }
      }
      out.depth_m[idx] = depth;
      float noise = 0.0f;
      if (s_.noise && s_.rgb_noise_sigma > 0.0f) {
        const std::uint64_t h = hash3(noise_key, idx, 1);
        noise = s_.rgb_noise_sigma * fast_normal_from(h);
      }
      if (s_.gray) {
        out.color[idx] = to_u8((0.299f * c.r + 0.587f * c.g + 0.114f * c.b) * 255.0f + noise);
      } else {
        std::uint8_t* px = &out.color[3 * idx];
        px[0] = to_u8(c.r * 255.0f + noise);
        px[1] = to_u8(c.g * 255.0f + noise);
        px[2] = to_u8(c.b * 255.0f + noise);
      }
    }
  }
}

float Renderer::distance_to_static_surface(Vec3f p) const {
  float best = std::min(std::abs(p.z), std::abs(p.z - scene_.ceiling_z_m));
  for (const auto& b : scene_.boxes) {
    float outside = 0.0f, inside = -std::numeric_limits<float>::max();
    for (int i = 0; i < 3; ++i) {
      const float c = 0.5f * (b.box.lo[i] + b.box.hi[i]);
      const float h = 0.5f * (b.box.hi[i] - b.box.lo[i]);
      const float d = std::abs(p[i] - c) - h;
      outside += d > 0 ? d * d : 0.0f;
      inside = std::max(inside, d);
    }
    best = std::min(best, outside > 0 ? std::sqrt(outside) : -inside);
  }
  return best;
}

}  // namespace vigs::sim
