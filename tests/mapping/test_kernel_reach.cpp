// The blending kernels skip a Gaussian for a row or an 8-pixel run it cannot reach
// (kernel_reach, RasterSettings::skip_out_of_reach). The bound must hold (every pixel that passes
// the kernels' test is inside it) and be tight (else it skips nothing), and the renders and
// gradients with the skip must be bit-identical to those without.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "mapping/raster_simd.hpp"
#include "mapping/rasterizer.hpp"
#include "test_scene.hpp"

namespace vigs::mapping {
namespace {

TEST(KernelReach, BoundsTheEllipseTheKernelsBlendAndIsTight) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    // a random positive definite 2D covariance, inverted into the kernels' conic
    const double sx = 0.5 + 20 * u(rng), sy = 0.3 + 5 * u(rng), th = 3.2 * u(rng);
    const double c = std::cos(th), s = std::sin(th);
    const double a = c * c * sx * sx + s * s * sy * sy + 0.3;
    const double b = c * s * (sx * sx - sy * sy);
    const double d = s * s * sx * sx + c * c * sy * sy + 0.3;
    const double det = a * d - b * b;
    const float conic[3] = {static_cast<float>(d / det), static_cast<float>(-b / det),
                            static_cast<float>(a / det)};
    const float opacity = static_cast<float>(0.02 + 0.97 * u(rng));
    const float cut = sigma_cutoff(opacity, 1.0 / 255.0);
    float rx = 0, ry = 0;
    kernel_reach(conic, cut, rx, ry);
    // the farthest pixel offsets (quarter-pixel grid) that pass sigma <= cut
    float far_x = 0, far_y = 0;
    const int lim_x = static_cast<int>(4 * (rx + 2)), lim_y = static_cast<int>(4 * (ry + 2));
    for (int j = -lim_y; j <= lim_y; ++j)
      for (int i = -lim_x; i <= lim_x; ++i) {
        const float dx = 0.25f * static_cast<float>(i), dy = 0.25f * static_cast<float>(j);
        const float sigma = 0.5f * (conic[0] * dx * dx + conic[2] * dy * dy) + conic[1] * dx * dy;
        if (sigma < 0 || sigma > cut) continue;
        far_x = std::max(far_x, std::abs(dx));
        far_y = std::max(far_y, std::abs(dy));
      }
    ASSERT_LE(far_x, rx) << "trial " << trial;
    ASSERT_LE(far_y, ry) << "trial " << trial;
    // tight: within the grid step and the 1 % slack of the true extent
    EXPECT_GT(far_x, 0.98f * rx - 0.3f) << "trial " << trial;
    EXPECT_GT(far_y, 0.98f * ry - 0.3f) << "trial " << trial;
  }
  float rx = 0, ry = 0;
  const float not_pd[3] = {1.0f, 2.0f, 1.0f};
  kernel_reach(not_pd, 5.0f, rx, ry);
  EXPECT_TRUE(std::isinf(rx) && std::isinf(ry));  // no bound where the kernels' test has none
}

void expect_same_with_and_without_skip(bool simd, bool avx512 = false) {
  const RenderCamera cam = test::small_camera(200, 150, 160.0);
  // small and elongated Gaussians, faint and opaque: most miss most rows of their tiles
  const GaussianMap g = test::random_gaussians<float>(2500, 11, 0.02, 0.99, -4.5, -1.5);
  RasterSettings with, without;
  with.use_simd = without.use_simd = simd;
  with.use_avx512 = without.use_avx512 = avx512;
  without.skip_out_of_reach = false;
  Rasterizer<float> ra(with), rb(without);
  RenderResult<float> a, b;
  ra.forward(g, cam, a);
  rb.forward(g, cam, b);
  ASSERT_EQ(ra.used_simd(), simd && avx2_kernel_available());
  ASSERT_EQ(ra.used_avx512(), simd && avx512 && avx512_kernel_available());
  EXPECT_EQ(a.color, b.color);
  EXPECT_EQ(a.depth, b.depth);
  EXPECT_EQ(a.final_T, b.final_T);
  EXPECT_EQ(a.n_contrib, b.n_contrib);
  const test::PixelGradients seed(a.depth.size());
  GaussianMap ga, gb;
  ra.backward(g, cam, a, seed.color.data(), seed.depth.data(), seed.alpha.data(), ga);
  rb.backward(g, cam, b, seed.color.data(), seed.depth.data(), seed.alpha.data(), gb);
  EXPECT_EQ(ga.mean_w, gb.mean_w);
  EXPECT_EQ(ga.log_scale, gb.log_scale);
  EXPECT_EQ(ga.quat_wxyz, gb.quat_wxyz);
  EXPECT_EQ(ga.opacity_logit, gb.opacity_logit);
  EXPECT_EQ(ga.color_rgb, gb.color_rgb);
  // the scene must give the skip something to do, or the test shows nothing
  double lit = 0;
  for (float t : a.final_T) lit += t < 0.99f ? 1 : 0;
  EXPECT_GT(lit, 0.5 * static_cast<double>(a.final_T.size()));
}

TEST(KernelReach, ScalarKernelsGiveBitIdenticalRenderAndGradients) {
  expect_same_with_and_without_skip(false);
}

TEST(KernelReach, Avx2KernelsGiveBitIdenticalRenderAndGradients) {
  if (!avx2_kernel_available()) GTEST_SKIP() << "no AVX2 kernel on this CPU/architecture";
  expect_same_with_and_without_skip(true, false);
}

TEST(KernelReach, Avx512KernelsGiveBitIdenticalRenderAndGradients) {
  if (!avx512_kernel_available()) GTEST_SKIP() << "no AVX-512 kernel on this CPU/architecture";
  expect_same_with_and_without_skip(true, true);
}

/// Tile Gaussians around and inside `rect` with random reach; some without a row bound
/// (infinite reach_y) and some with a NaN row.
std::vector<TileGaussian<float>> random_tile_gaussians(const TileRect& rect, int count,
                                                       std::mt19937& rng) {
  std::uniform_real_distribution<float> pos(-30.0f, 90.0f), reach(0.0f, 12.0f);
  std::vector<TileGaussian<float>> gs(static_cast<std::size_t>(count));
  for (int k = 0; k < count; ++k) {
    TileGaussian<float>& g = gs[static_cast<std::size_t>(k)];
    g = {};
    g.x = static_cast<float>(rect.x0) + pos(rng) * static_cast<float>(rect.x1 - rect.x0) / 60;
    g.y = static_cast<float>(rect.y0) + pos(rng) * static_cast<float>(rect.y1 - rect.y0) / 60;
    g.reach_x = reach(rng);
    g.reach_y = reach(rng);
    if (k % 13 == 5) g.reach_y = std::numeric_limits<float>::infinity();
    if (k % 17 == 3) g.y = std::numeric_limits<float>::quiet_NaN();
  }
  return gs;
}

// The AVX2 kernels blend each 8-pixel run over a list of the tile's Gaussians that can reach it
// (fill_tile_runs_avx2, from row and column bit masks). Every list must be exactly the Gaussians
// out_of_reach() keeps, in tile order, for full and edge tiles, tiles too tall for the masks,
// and Gaussians without a bound (infinite or NaN reach).
TEST(KernelReach, Avx2RunListsHoldExactlyTheGaussiansThatReachEachRun) {
  if (!avx2_kernel_available()) GTEST_SKIP() << "no AVX2 kernel on this CPU/architecture";
  std::mt19937 rng(7);
  const TileRect rects[] = {{32, 48, 48, 64}, {704, 464, 713, 469}, {0, 0, 16, 40}, {3, 5, 4, 6}};
  for (const TileRect& rect : rects) {
    for (const int count : {0, 1, 7, 8, 9, 61}) {
      const std::vector<TileGaussian<float>> gs = random_tile_gaussians(rect, count, rng);
      std::vector<int> runs(tile_run_scratch(rect, count), -1);
      fill_tile_runs_avx2(rect, gs.data(), count, runs.data());
      const int n_runs = tile_runs(rect);
      int run = 0, reached = 0;
      for (int py = rect.y0; py < rect.y1; ++py) {
        for (int x0 = rect.x0; x0 < rect.x1; x0 += 8, ++run) {
          const int x1 = std::min(x0 + 8, rect.x1) - 1;
          std::vector<int> want;
          for (int k = 0; k < count; ++k)
            if (!out_of_reach(gs[static_cast<std::size_t>(k)], float(x0), float(x1), float(py)))
              want.push_back(k);
          const int* list = runs.data() + n_runs + run * count;
          const std::vector<int> got(list, list + runs[static_cast<std::size_t>(run)]);
          ASSERT_EQ(got, want) << "tile " << rect.x0 << "," << rect.y0 << " count " << count
                               << " row " << py << " x " << x0;
          reached += static_cast<int>(want.size());
        }
      }
      if (count > 8 && n_runs >= 8) {
        EXPECT_GT(reached, 0);
        EXPECT_LT(reached, n_runs * count);  // some runs are out of some Gaussians' reach
      }
    }
  }
}

// The AVX-512 kernels blend each 8 x 2 pixel block over a list of the tile's Gaussians that can
// reach it (fill_tile_blocks_avx512). Every list must be exactly the Gaussians out_of_reach()
// keeps for one of the block's rows over its columns, in tile order, for full and edge tiles
// (odd rows, narrow columns), tiles too tall for the row masks, and Gaussians without a bound.
TEST(KernelReach, Avx512BlockListsHoldExactlyTheGaussiansThatReachEachBlock) {
  if (!avx512_kernel_available()) GTEST_SKIP() << "no AVX-512 kernel on this CPU/architecture";
  std::mt19937 rng(9);
  const TileRect rects[] = {
      {32, 48, 48, 64}, {704, 464, 713, 469}, {0, 0, 16, 40}, {3, 5, 4, 6}, {16, 0, 32, 21}};
  for (const TileRect& rect : rects) {
    for (const int count : {0, 1, 15, 16, 17, 61}) {
      const std::vector<TileGaussian<float>> gs = random_tile_gaussians(rect, count, rng);
      std::vector<int> blocks(tile_block_scratch(rect, count), -1);
      fill_tile_blocks_avx512(rect, gs.data(), count, blocks.data());
      const int n_blocks = tile_blocks(rect);
      int block = 0, reached = 0;
      for (int y0 = rect.y0; y0 < rect.y1; y0 += 2) {
        for (int x0 = rect.x0; x0 < rect.x1; x0 += 8, ++block) {
          const int x1 = std::min(x0 + 8, rect.x1) - 1, y1 = std::min(y0 + 2, rect.y1);
          std::vector<int> want;
          for (int k = 0; k < count; ++k) {
            bool reach_any = false;
            for (int y = y0; y < y1; ++y)
              reach_any = reach_any || !out_of_reach(gs[static_cast<std::size_t>(k)], float(x0),
                                                     float(x1), float(y));
            if (reach_any) want.push_back(k);
          }
          const int* list = blocks.data() + n_blocks + block * count;
          const std::vector<int> got(list, list + blocks[static_cast<std::size_t>(block)]);
          ASSERT_EQ(got, want) << "tile " << rect.x0 << "," << rect.y0 << " count " << count
                               << " block at " << x0 << "," << y0;
          reached += static_cast<int>(want.size());
        }
      }
      ASSERT_EQ(block, n_blocks);
      if (count > 16 && n_blocks >= 8) {
        EXPECT_GT(reached, 0);
        EXPECT_LT(reached, n_blocks * count);  // some blocks are out of some Gaussians' reach
      }
    }
  }
}

}  // namespace
}  // namespace vigs::mapping
