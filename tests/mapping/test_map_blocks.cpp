// Block culling (map_blocks.hpp): a forward pass with the blocks renders exactly what it renders
// without them (every culled block held only Gaussians project_gaussian() would cull), it does
// cull, and the bounds stay true while the optimiser moves Gaussians, prunes and the map grows.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "mapping/map_optimizer.hpp"
#include "mapping/see_through.hpp"

namespace vigs::mapping {
namespace {

/// `clusters` clusters of kBlock Gaussians each, in insertion order as keyframes give them,
/// spread over a 40 m square at heights 0-3 m; scales from 7 mm to 0.6 m. Tight: each cluster
/// within a millimetre and scales under 3 mm, so that a block's bound is its Gaussians' own
/// and a block at an image edge tests the cull at its threshold.
GaussianMap clustered_map(int clusters, unsigned seed, bool tight = false) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  GaussianMap g;
  for (int c = 0; c < clusters; ++c) {
    const float cx = 40.0f * u(rng) - 20.0f, cy = 40.0f * u(rng) - 20.0f;
    const float spread = tight ? 0.001f : 0.2f + 2.0f * u(rng);
    const float ls0 = tight ? -8.0f : -5.0f;
    for (std::size_t k = 0; k < MapBlocks::kBlock; ++k) {
      const float mean[3] = {cx + spread * (u(rng) - 0.5f), cy + spread * (u(rng) - 0.5f),
                             3.0f * u(rng)};
      const float big = !tight && u(rng) < 0.02f ? 2.5f : 0.0f;  // a few large ones (0.6 m)
      const float ls[3] = {ls0 + big + 2.0f * u(rng), ls0 + 2.0f * u(rng), ls0 + 2.0f * u(rng)};
      const float q[4] = {1.0f, u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f};
      const float rgb[3] = {u(rng), u(rng), u(rng)};
      g.push_back(mean, ls, q, 4.0f * u(rng) - 2.0f, rgb);
    }
  }
  return g;
}

/// A camera at (x, y, 1.5 m) looking horizontally with heading `yaw`.
RenderCamera camera(double x, double y, double yaw, int w = 96, int h = 64) {
  PinholeCamera k{w, h, 0.8 * w, 0.8 * w, 0.5 * w - 0.5, 0.5 * h - 0.5};
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  // camera z forward along the heading, x right, y down
  const Eigen::Vector3d fwd(std::cos(yaw), std::sin(yaw), 0.0);
  const Eigen::Vector3d down(0.0, 0.0, -1.0);
  const Eigen::Vector3d right = down.cross(fwd);
  T_w_c.linear().col(0) = right;
  T_w_c.linear().col(1) = down;
  T_w_c.linear().col(2) = fwd;
  T_w_c.translation() = Eigen::Vector3d(x, y, 1.5);
  return RenderCamera::from(k, T_w_c);
}

std::vector<RenderCamera> cameras(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<RenderCamera> cams;
  for (int i = 0; i < n; ++i)
    cams.push_back(camera(44.0 * u(rng) - 22.0, 44.0 * u(rng) - 22.0, 6.3 * u(rng)));
  return cams;
}

void expect_same_render(const GaussianMap& g, const RenderCamera& cam, MapBlocks& blocks,
                        std::size_t& culled, std::size_t& projected) {
  Rasterizer<float> with, without;
  RenderResult<float> a, b;
  with.forward(g, cam, a, &blocks);
  without.forward(g, cam, b);
  ASSERT_EQ(with.visible_ids(), without.visible_ids());
  for (const int i : with.visible_ids())
    ASSERT_EQ(with.projected(static_cast<std::size_t>(i))->radius,
              without.projected(static_cast<std::size_t>(i))->radius);
  EXPECT_EQ(a.color, b.color);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.final_T, b.final_T);
  culled += with.culled_blocks();
  projected += blocks.blocks() - with.culled_blocks();
}

TEST(MapBlocks, RendersExactlyWhatEveryGaussianProjectedRenders) {
  for (const bool tight : {false, true}) {
    const GaussianMap g = clustered_map(tight ? 150 : 60, 3, tight);
    MapBlocks blocks;
    std::size_t culled = 0, projected = 0, visible = 0;
    for (const RenderCamera& cam : cameras(40, 5)) {
      expect_same_render(g, cam, blocks, culled, projected);
      Rasterizer<float> r;
      RenderResult<float> out;
      r.forward(g, cam, out);
      visible += r.visible_ids().size();
    }
    EXPECT_GT(visible, 0u);
    // the blocks do cull: most of the map is behind or beside any one camera
    EXPECT_GT(culled, 2 * projected) << "culled " << culled << " projected " << projected;
  }
}

// With a team, whichever member claims a block computes its bound: the same bounds, so the same
// cull for every block and camera, at the first update, after a block moved and after a
// compaction's invalidate().
TEST(MapBlocks, ATeamComputesTheSameBounds) {
  GaussianMap g = clustered_map(60, 11);
  rt::WorkerTeam team(2);
  MapBlocks serial, shared;
  const RasterSettings rs;
  const std::vector<RenderCamera> cams = cameras(40, 13);
  const auto expect_same_cull = [&] {
    serial.update(g);
    shared.update(g, &team);
    ASSERT_EQ(serial.blocks(), shared.blocks());
    std::size_t culled = 0;
    for (const RenderCamera& cam : cams) {
      for (std::size_t b = 0; b < serial.blocks(); ++b) {
        const bool seen = serial.may_be_visible(b, cam, rs);
        ASSERT_EQ(seen, shared.may_be_visible(b, cam, rs)) << "block " << b;
        culled += seen ? 0 : 1;
      }
    }
    EXPECT_GT(culled, 0u);
  };
  expect_same_cull();
  std::vector<int> moved;  // block 5 moves 4 m
  for (std::size_t i = 5 * MapBlocks::kBlock; i < 6 * MapBlocks::kBlock; ++i) {
    g.mean_w[3 * i] += 4.0f;
    moved.push_back(static_cast<int>(i));
  }
  serial.mark_changed(moved);
  shared.mark_changed(moved);
  expect_same_cull();
  serial.invalidate();
  shared.invalidate();
  expect_same_cull();
}

TEST(MapBlocks, StayTrueWhileTheOptimiserMovesPrunesAndTheMapGrows) {
  GaussianMap g = clustered_map(80, 7, true);
  config::MappingSettings s;
  s.adam.lr_mean = 1.0;  // metres a step, well past the cull's slack: blocks must follow
  s.adam.lr_log_scale = 0.05;
  s.prune_every = 7;
  s.prune.min_opacity = 0.3;  // prunes something every time
  MapOptimizer opt(s, nullptr);
  ASSERT_NE(opt.blocks(), nullptr);
  const std::vector<RenderCamera> cams = cameras(10, 9);
  std::vector<float> target(3 * 96 * 64, 0.5f);
  std::mt19937 rng(1);
  std::size_t culled = 0, projected = 0;
  const std::size_t size0 = g.size();
  for (std::size_t it = 0; it < cams.size(); ++it) {
    (void)opt.iterate(g, TrainingView{cams[it], target.data(), nullptr});
    if (it % 4 == 2) {  // the map grows: half a block copied, moved 3 m
      const std::size_t from = (rng() % (g.size() / MapBlocks::kBlock)) * MapBlocks::kBlock;
      for (std::size_t i = from; i < from + MapBlocks::kBlock / 2; ++i) {
        const float mean[3] = {g.mean_w[3 * i] + 3.0f, g.mean_w[3 * i + 1], g.mean_w[3 * i + 2]};
        g.push_back(mean, &g.log_scale[3 * i], &g.quat_wxyz[4 * i], 2.0f, &g.color_rgb[3 * i]);
      }
    }
    // the moved Gaussians were in view: sweep the image edges across them
    const RenderCamera& c = cams[it];
    const Eigen::Vector3d p_w =
        -Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(c.R_c_w).transpose() *
        Eigen::Vector3d(c.t_c_w[0], c.t_c_w[1], c.t_c_w[2]);
    const double yaw = std::atan2(c.R_c_w[7], c.R_c_w[6]);  // camera z axis in the world
    for (int k = -12; k <= 12; ++k)
      expect_same_render(g, camera(p_w.x(), p_w.y(), yaw + 0.04 * k), *opt.blocks(), culled,
                         projected);
    if (HasFailure()) return;
  }
  EXPECT_NE(g.size(), size0);
  EXPECT_GT(culled, 0u);
}

TEST(MapBlocks, SeeThroughVotesAreTheSameWithBlocks) {
  const GaussianMap g = clustered_map(60, 11);
  config::SeeThroughSettings st;
  st.enabled = true;
  st.min_count = 1;
  SeeThrough with(st), without(st);
  MapBlocks blocks;
  std::vector<char> keep_with, keep_without;
  std::size_t condemned = 0;
  std::vector<float> depth(96 * 64);
  int k = 0;
  for (const RenderCamera& cam : cameras(30, 13)) {
    std::fill(depth.begin(), depth.end(), 2.0f + 0.5f * static_cast<float>(k++ % 12));
    const std::size_t a = with.vote(g, cam, depth.data(), keep_with, &blocks);
    const std::size_t b = without.vote(g, cam, depth.data(), keep_without);
    ASSERT_EQ(a, b);
    ASSERT_EQ(keep_with, keep_without);
    condemned += a;
  }
  EXPECT_GT(condemned, 0u);
}

}  // namespace
}  // namespace vigs::mapping
