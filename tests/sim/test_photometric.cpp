#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/config/robot_config.hpp"
#include "sim/simulator.hpp"

namespace vigs::sim {
namespace {

/// Mean absolute difference (grey levels, all channels) between frame A and frame B sampled
/// bilinearly where A's back-projected depth lands in B, for the pose T_w_cb given.
/// Pixels occluded in B (depth disagrees by > 3 cm) are skipped.
double warp_error(const PinholeCamera& cam, const RgbdFrame& a, const geometry::Pose& T_w_ca,
                  const RgbdFrame& b, const geometry::Pose& T_w_cb, int* used) {
  const geometry::Pose T_cb_ca = T_w_cb.inverse() * T_w_ca;
  double sum = 0.0;
  int n = 0;
  for (int v = 0; v < a.height; v += 3) {
    for (int u = 0; u < a.width; u += 3) {
      const float z = a.depth_m[static_cast<std::size_t>(v) * a.width + u];
      if (z <= 0.0f || z > 8.0f) continue;
      const Eigen::Vector3d p = T_cb_ca * cam.back_project(u, v, z);
      if (p.z() < 0.2) continue;
      const Eigen::Vector2d q = cam.project(p);
      const int x0 = static_cast<int>(std::floor(q.x())), y0 = static_cast<int>(std::floor(q.y()));
      if (x0 < 0 || y0 < 0 || x0 + 1 >= b.width || y0 + 1 >= b.height) continue;
      const float zb = b.depth_m[static_cast<std::size_t>(y0) * b.width + x0];
      if (std::abs(zb - p.z()) > 0.03) continue;  // occluded or a hole
      const double fx = q.x() - x0, fy = q.y() - y0;
      for (int c = 0; c < 3; ++c) {
        auto at = [&](int x, int y) {
          return static_cast<double>(b.color[3 * (static_cast<std::size_t>(y) * b.width + x) + c]);
        };
        const double s = (1 - fx) * (1 - fy) * at(x0, y0) + fx * (1 - fy) * at(x0 + 1, y0) +
                         (1 - fx) * fy * at(x0, y0 + 1) + fx * fy * at(x0 + 1, y0 + 1);
        sum += std::abs(s - a.color[3 * (static_cast<std::size_t>(v) * a.width + u) + c]);
        ++n;
      }
    }
  }
  *used = n / 3;
  return n > 0 ? sum / n : 1e9;
}

// The textures are view-consistent and informative: warping one frame into the next with the
// true relative pose matches colours closely, and a 3 cm pose error does not.
TEST(Photometric, TexturesAreViewConsistentAndPoseSensitive) {
  config::RobotConfig cfg;
  cfg.sim.humans = 0;
  cfg.sim.seconds = 60.0;
  Simulator sim(cfg);
  RenderSettings rs = sim.renderer().settings();
  rs.noise = false;
  const Renderer clean(sim.scene(), sim.camera(), rs);
  const PeopleSnapshot nobody;
  for (double t : {12.0, 27.0, 45.0}) {
    RgbdFrame a, b;
    const geometry::Pose T_a = sim.camera_pose(t), T_b = sim.camera_pose(t + 0.1);
    clean.render(T_a, nobody, 0, a);
    clean.render(T_b, nobody, 0, b);
    int used = 0, used_off = 0;
    const double e_true = warp_error(sim.camera(), a, T_a, b, T_b, &used);
    geometry::Pose T_off = T_b;
    T_off.translation() += T_b.linear() * Eigen::Vector3d(0.03, 0.0, 0.0);  // 3 cm right
    const double e_off = warp_error(sim.camera(), a, T_a, b, T_off, &used_off);
    EXPECT_GT(used, 5000) << t;
    EXPECT_LT(e_true, 2.0) << t;          // measured 1.0-1.3 grey levels
    EXPECT_GT(e_off, 3.0 * e_true) << t;  // measured 3.6-5.5x
    std::printf("t=%.0f: photometric error %.2f (true pose) vs %.2f (3 cm off), %d pixels\n", t,
                e_true, e_off, used);
  }
}

}  // namespace
}  // namespace vigs::sim
