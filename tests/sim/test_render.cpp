#include <gtest/gtest.h>

#include <cmath>

#include "core/config/robot_config.hpp"
#include "sim/floor_plan.hpp"
#include "sim/rng.hpp"
#include "sim/simulator.hpp"

namespace vigs::sim {
namespace {

config::RobotConfig test_config(int humans, int seed) {
  config::RobotConfig cfg;
  cfg.sim.humans = humans;
  cfg.sim.seed = seed;
  cfg.sim.seconds = 5.0;
  return cfg;
}

TEST(Bvh, ClosestHitMatchesBruteForce) {
  const Scene s = make_preset("office", 4);
  std::vector<Aabb> boxes;
  for (const auto& b : s.boxes) boxes.push_back(b.box);
  const Bvh bvh(boxes);
  Rng rng(1, 2);
  for (int i = 0; i < 3000; ++i) {
    const Vec3f o{static_cast<float>(rng.uniform(0, 64)), static_cast<float>(rng.uniform(0, 64)),
                  static_cast<float>(rng.uniform(0.2, 2.8))};
    const Vec3f d{static_cast<float>(rng.normal()), static_cast<float>(rng.normal()),
                  static_cast<float>(0.3 * rng.normal())};
    const Ray ray = Ray::make(o, d);
    float t_bvh = 1e30f;
    bvh.closest_hit(ray, t_bvh, [&](std::uint32_t p, float& t) {
      t = std::min(t, ray_box_entry(ray, boxes[p], 0.0f, t));
    });
    float t_brute = 1e30f;
    for (const auto& b : boxes) t_brute = std::min(t_brute, ray_box_entry(ray, b, 0.0f, t_brute));
    EXPECT_EQ(t_bvh, t_brute) << i;
  }
}

/// Back-projects every 5th pixel of a noise-free frame and measures how far the point lies from
/// the nearest scene surface (static boxes, floor, ceiling, or a person at that instant).
/// Measured: below 2e-5 m (single-precision casting). The 1e-4 m bound still catches a
/// half-pixel convention error, which puts points ~1 mm off oblique walls at 1 m.
TEST(Render, NoiseFreeDepthBackProjectsOntoTheSceneSurfaces) {
  config::RobotConfig cfg = test_config(60, 3);
  cfg.sim.preset = "apartment";  // small: the brute-force distance check stays quick
  Simulator sim(cfg);
  RenderSettings rs = sim.renderer().settings();
  rs.noise = false;
  const Renderer clean(sim.scene(), sim.camera(), rs);
  int checked = 0, on_people = 0;
  for (double t : {1.0, 9.0, 17.5, 31.0}) {
    const PeopleSnapshot people(sim.walkers(), t);
    RgbdFrame f;
    const geometry::Pose T_w_c = sim.camera_pose(t);
    clean.render(T_w_c, people, 0, f);
    for (int v = 0; v < f.height; v += 5) {
      for (int u = 0; u < f.width; u += 5) {
        const float z = f.depth_m[static_cast<std::size_t>(v) * f.width + u];
        if (z <= 0.0f) continue;
        const Eigen::Vector3d p = T_w_c * sim.camera().back_project(u, v, z);
        const Vec3f pw{static_cast<float>(p.x()), static_cast<float>(p.y()),
                       static_cast<float>(p.z())};
        const float d_static = clean.distance_to_static_surface(pw);
        const float d_people = people.distance_to_surface(pw);
        EXPECT_LT(std::min(d_static, d_people), 1e-4f) << u << "," << v << " t=" << t;
        on_people += d_people < d_static;
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 20000);
  EXPECT_GT(on_people, 0);  // the 60 people are seen too
}

TEST(Render, SensorModelNoiseGrowsWithDepthSquaredHolesAndRange) {
  Simulator sim(test_config(0, 5));
  RenderSettings rs = sim.renderer().settings();
  rs.noise = false;
  const Renderer clean(sim.scene(), sim.camera(), rs);
  const PeopleSnapshot nobody;
  double s_near = 0, s_far = 0, z_near = 0, z_far = 0;
  int n_near = 0, n_far = 0, grazing = 0, grazing_holes = 0, beyond = 0;
  for (double t : {4.0, 12.0, 40.0}) {
    RgbdFrame noisy, exact;
    sim.render_at(t, 1, noisy);
    const geometry::Pose T_w_c = sim.camera_pose(t);
    clean.render(T_w_c, nobody, 0, exact);
    for (int v = 0; v < exact.height; v += 2) {
      for (int u = 0; u < exact.width; u += 2) {
        const std::size_t i = static_cast<std::size_t>(v) * exact.width + u;
        const float z = exact.depth_m[i];
        if (z > 0 && noisy.depth_m[i] > 0) {
          const double e = noisy.depth_m[i] - z;
          if (z > 1.0f && z < 2.0f) s_near += e * e, z_near += z * z, ++n_near;
          if (z > 5.0f && z < 7.0f) s_far += e * e, z_far += z * z, ++n_far;
        }
        // Exact incidence from a fresh ray cast.
        const Eigen::Vector3d dc((u - sim.camera().cx_px) / sim.camera().fx_px,
                                 (v - sim.camera().cy_px) / sim.camera().fy_px, 1.0);
        const Eigen::Vector3d dw = T_w_c.linear() * dc;
        const Ray ray = Ray::make(
            {static_cast<float>(T_w_c.translation().x()),
             static_cast<float>(T_w_c.translation().y()),
             static_cast<float>(T_w_c.translation().z())},
            {static_cast<float>(dw.x()), static_cast<float>(dw.y()), static_cast<float>(dw.z())});
        Hit hit;
        if (!clean.cast(ray, nullptr, hit)) continue;
        const double cos_inc =
            std::abs(hit.normal.x * dw.x() + hit.normal.y * dw.y() + hit.normal.z * dw.z()) /
            dw.norm();
        if (cos_inc < rs.hole_cos) {
          ++grazing;
          grazing_holes += noisy.depth_m[i] == 0.0f;
        }
        if (hit.t > rs.max_depth_m + 0.5f) beyond += noisy.depth_m[i] == 0.0f ? 0 : 1;
      }
    }
  }
  ASSERT_GT(n_near, 1000);
  ASSERT_GT(n_far, 1000);
  // sigma = base + k z^2: the ratio of RMS errors follows the ratio of z^2.
  const double sigma_near = std::sqrt(s_near / n_near), sigma_far = std::sqrt(s_far / n_far);
  const double k = rs.depth_noise_quadratic_per_m, b = rs.depth_noise_base_m;
  EXPECT_NEAR(sigma_near, b + k * z_near / n_near, 0.15 * (b + k * z_near / n_near));
  EXPECT_NEAR(sigma_far, b + k * z_far / n_far, 0.15 * (b + k * z_far / n_far));
  EXPECT_GT(grazing, 100);
  EXPECT_EQ(grazing_holes, grazing);  // every grazing pixel is a hole
  EXPECT_EQ(beyond, 0);               // nothing measured beyond the range
}

TEST(Render, DeterministicForASeedAndIndependentOfThreadCount) {
  config::RobotConfig cfg = test_config(24, 11);
  cfg.sim.render_threads = 2;
  Simulator a(cfg), b(cfg);
  cfg.sim.render_threads = 1;
  Simulator single(cfg);
  cfg.sim.render_threads = 2;
  cfg.sim.seed = 12;
  Simulator other(cfg);
  RgbdFrame fa, fb, fs, fo;
  a.render_at(3.0, 60, fa);
  b.render_at(3.0, 60, fb);
  single.render_at(3.0, 60, fs);
  other.render_at(3.0, 60, fo);
  EXPECT_EQ(fa.color, fb.color);
  EXPECT_EQ(fa.depth_m, fb.depth_m);
  EXPECT_EQ(fa.color, fs.color);
  EXPECT_EQ(fa.depth_m, fs.depth_m);
  EXPECT_EQ(fa.dynamic_mask, fs.dynamic_mask);
  EXPECT_NE(fa.color, fo.color);
}

/// A wall 5 m ahead, one person standing 2 m ahead; the camera 1 m up, pitched 10 degrees up so
/// that the person's feet (where person and floor meet) are out of view.
struct OnePersonBeforeAWall {
  Scene scene;
  std::vector<Walker> person;
  PinholeCamera camera{160, 120, 100.0, 100.0, 79.5, 59.5};
  geometry::Pose T_w_c = geometry::Pose::Identity();
  OnePersonBeforeAWall() {
    scene.ceiling_z_m = 3.0f;
    SceneBox wall;
    wall.box.lo = Vec3f{5.0f, -20.0f, 0.0f};
    wall.box.hi = Vec3f{5.2f, 20.0f, 3.0f};
    scene.boxes.push_back(wall);
    Walker w;  // paces along y through x = 2 m; standing still at (2, 0)
    w.a = {2.0, -1.0};
    w.b = {2.0, 1.0};
    w.speed_mps = 0.0;
    w.phase_m = 1.0;
    person.push_back(w);
    Eigen::Matrix3d R_w_c0;  // camera x right = -y, y down = -z, z forward = +x
    R_w_c0.col(0) = Eigen::Vector3d(0, -1, 0);
    R_w_c0.col(1) = Eigen::Vector3d(0, 0, -1);
    R_w_c0.col(2) = Eigen::Vector3d(1, 0, 0);
    T_w_c.linear() = Eigen::AngleAxisd(-10.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()) * R_w_c0;
    T_w_c.translation() = Eigen::Vector3d(0.0, 0.0, 1.0);
  }
};

TEST(Render, DynamicMaskIsSetExactlyWherePersonIsTheClosestSurface) {
  const OnePersonBeforeAWall v;
  RenderSettings exact;
  exact.noise = false;
  exact.hole_cos = exact.dropout_cos = 0.0f;  // no holes: every pixel has its surface's depth
  const Renderer renderer(v.scene, v.camera, exact);
  RgbdFrame with, without;
  renderer.render(v.T_w_c, PeopleSnapshot(v.person, 0.0), 0, with);
  renderer.render(v.T_w_c, PeopleSnapshot(), 0, without);
  const std::size_t n = static_cast<std::size_t>(v.camera.width_px) * v.camera.height_px;
  ASSERT_EQ(with.dynamic_mask.size(), n);
  ASSERT_EQ(without.dynamic_mask.size(), n);
  std::size_t person_px = 0;
  for (std::size_t i = 0; i < n; ++i) {
    // Ground truth, independently: the person is the closest surface exactly where removing
    // them changes the (noise-free) depth.
    const bool person = with.depth_m[i] != without.depth_m[i];
    EXPECT_EQ(with.dynamic_mask[i], person ? 255 : 0) << i;
    EXPECT_EQ(without.dynamic_mask[i], 0) << i;  // no people: all zero
    if (with.dynamic_mask[i] != 0) {
      ++person_px;
      // The person's parts lie within 0.4 m of where they stand, 2 m ahead (z of d is 1
      // there: the camera's axis is 10 degrees off the floor).
      EXPECT_GT(with.depth_m[i], 1.5f) << i;
      EXPECT_LT(with.depth_m[i], 2.5f) << i;
    }
  }
  EXPECT_GT(person_px, 500u);   // a person 2 m away covers a good part of the view
  EXPECT_LT(person_px, n / 2);  // and not all of it

  // With the sensor model, noise and holes change colour and depth but not the ground truth.
  const Renderer noisy(v.scene, v.camera, RenderSettings{});
  RgbdFrame measured;
  noisy.render(v.T_w_c, PeopleSnapshot(v.person, 0.0), 7, measured);
  EXPECT_EQ(measured.dynamic_mask, with.dynamic_mask);
}

TEST(Render, CameraKeepsClearOfWallsFurnitureAndPeopleAlongTheWholeRoute) {
  for (const char* preset : {"office", "apartment"}) {
    config::RobotConfig cfg = test_config(60, 2);
    cfg.sim.preset = preset;
    cfg.sim.seconds = 0.0;  // whole route
    Simulator sim(cfg);
    float min_static = 1e9f, min_people = 1e9f;
    for (double t = 0.0; t <= sim.duration_s(); t += 0.25) {
      const Eigen::Vector3d c = sim.camera_pose(t).translation();
      const Vec3f p{static_cast<float>(c.x()), static_cast<float>(c.y()),
                    static_cast<float>(c.z())};
      min_static = std::min(min_static, sim.renderer().distance_to_static_surface(p));
      min_people = std::min(min_people, PeopleSnapshot(sim.walkers(), t).distance_to_surface(p));
    }
    EXPECT_GT(min_static, 0.5f) << preset;  // measured 1.03 m (office), 0.63 m (apartment)
    EXPECT_GT(min_people, 0.1f) << preset;  // measured 0.41 m, 0.155 m: nobody walks into it
  }
}

TEST(Render, GrayOptionGivesMono8) {
  config::RobotConfig cfg = test_config(0, 1);
  cfg.sim.gray = true;
  Simulator sim(cfg);
  RgbdFrame f;
  sim.render_at(1.0, 0, f);
  EXPECT_TRUE(f.gray);
  EXPECT_EQ(f.color.size(), static_cast<std::size_t>(720 * 480));
}

}  // namespace
}  // namespace vigs::sim
