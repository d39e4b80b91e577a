// Forward rendering: closed-form single Gaussians, SIMD against scalar, any team size against one
// thread (bit-identical), and the early-termination rules.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "mapping/depth_key_sort.hpp"
#include "mapping/raster_simd.hpp"
#include "mapping/rasterizer.hpp"
#include "test_scene.hpp"

namespace vigs::mapping {
namespace {

RenderCamera identity_camera(int w, int h, double f, double cx, double cy) {
  return RenderCamera::from(PinholeCamera{w, h, f, f, cx, cy}, Eigen::Isometry3d::Identity());
}

/// One forward render of `g` by the scalar or the AVX2 kernels.
RenderResult<float> render_with(const GaussianMap& g, const RenderCamera& cam, bool simd) {
  RasterSettings rs;
  rs.use_simd = simd;
  Rasterizer<float> ras(rs);
  RenderResult<float> r;
  ras.forward(g, cam, r);
  return r;
}

/// Renders one Gaussian at camera-frame (0, 0, z) whose axes are rotated by theta about the
/// optical axis and compares every pixel with the closed form
///   Sigma_2D = (f/z)^2 R2 diag(sx^2, sy^2) R2^T + 0.3 I,  alpha = min(0.99, o exp(-d^T C d / 2)).
/// `tile_pairs`: where given, the Gaussian-tile pairs the render used.
void check_closed_form(double theta, double sx, double sy, double opacity,
                       std::size_t* tile_pairs = nullptr) {
  const int W = 64, H = 64;
  const double f = 100, z = 2.0, cx = 31.0, cy = 33.0;
  const RenderCamera cam = identity_camera(W, H, f, cx, cy);
  GaussianMap g;
  const float mean[3] = {0.0f, 0.0f, static_cast<float>(z)};
  const float ls[3] = {static_cast<float>(std::log(sx)), static_cast<float>(std::log(sy)),
                       static_cast<float>(std::log(0.05))};
  const float q[4] = {static_cast<float>(std::cos(theta / 2)), 0.0f, 0.0f,
                      static_cast<float>(std::sin(theta / 2))};
  const float rgb[3] = {0.8f, 0.4f, 0.2f};
  g.push_back(mean, ls, q, static_cast<float>(std::log(opacity / (1 - opacity))), rgb);
  Rasterizer<float> ras;
  RenderResult<float> r;
  ras.forward(g, cam, r);

  const double k = f / z, c = std::cos(theta), s = std::sin(theta);
  const double a = k * k * (c * c * sx * sx + s * s * sy * sy) + 0.3;
  const double b = k * k * (c * s * (sx * sx - sy * sy));
  const double d = k * k * (s * s * sx * sx + c * c * sy * sy) + 0.3;
  const double det = a * d - b * b;
  const double ca = d / det, cb = -b / det, cc = a / det;
  const double mid = 0.5 * (a + d);
  const int radius = static_cast<int>(std::ceil(3 * std::sqrt(mid + std::sqrt(mid * mid - det))));
  ASSERT_TRUE(ras.projected(0).has_value());
  EXPECT_EQ(ras.projected(0)->radius, radius);
  int lit = 0;
  for (int v = 0; v < H; ++v) {
    for (int u = 0; u < W; ++u) {
      const double dx = cx - u, dy = cy - v;
      const double sigma = 0.5 * (ca * dx * dx + cc * dy * dy) + cb * dx * dy;
      double alpha = std::min(0.99, opacity * std::exp(-sigma));
      // pixels outside the Gaussian's tiles are never touched
      const bool in_tiles =
          std::floor((cx - radius) / 16) <= u / 16 && u / 16 <= std::floor((cx + radius) / 16) &&
          std::floor((cy - radius) / 16) <= v / 16 && v / 16 <= std::floor((cy + radius) / 16);
      if (alpha < 1.0 / 255.0 || !in_tiles) alpha = 0;
      lit += alpha > 0 ? 1 : 0;
      const int p = v * W + u;
      ASSERT_NEAR(r.color[3 * p], 0.8 * alpha, 2e-6) << u << "," << v;
      ASSERT_NEAR(r.color[3 * p + 1], 0.4 * alpha, 2e-6);
      ASSERT_NEAR(r.color[3 * p + 2], 0.2 * alpha, 2e-6);
      ASSERT_NEAR(r.depth[p], z * alpha, 4e-6);
      ASSERT_NEAR(r.alpha(p), alpha, 2e-6);
    }
  }
  EXPECT_GT(lit, 50);
  if (tile_pairs) *tile_pairs = ras.tile_pairs();
}

TEST(MappingRender, SingleIsotropicGaussianMatchesClosedForm) {
  check_closed_form(0.0, 0.1, 0.1, 0.8);
}

TEST(MappingRender, SingleRotatedAnisotropicGaussianMatchesClosedForm) {
  // theta = 30 degrees about the optical axis checks the w x y z quaternion order
  check_closed_form(M_PI / 6, 0.2, 0.05, 0.6);
}

// A flat disc seen edge-on: 20 px across, under a pixel down. Its 3-sigma square covers every
// tile of the 64x64 view; the pixels it can reach lie in two tile rows, and only those are
// binned (the render still matches the closed form at every pixel).
TEST(MappingRender, ANarrowGaussianIsBinnedOnlyIntoTheTilesItReaches) {
  std::size_t pairs = 0;
  check_closed_form(0.0, 0.4, 0.01, 0.9, &pairs);
  EXPECT_EQ(pairs, 8u);                                 // 16 with the square
  check_closed_form(M_PI / 2, 0.4, 0.01, 0.9, &pairs);  // standing: two tile columns
  EXPECT_EQ(pairs, 8u);
}

// Each tile's list is blended near to far whatever the Gaussians' ids (the float rasterizer sorts
// packed depth-and-id keys): the scene is inserted near to far and far to near, and rendered by
// the scalar and the AVX2 kernels.
TEST(MappingRender, OpaqueGaussianClampsAlphaAndStopsEarly) {
  const RenderCamera cam = identity_camera(32, 32, 50, 16, 16);
  const float ls[3] = {-1.0f, -1.0f, -1.0f}, q[4] = {1, 0, 0, 0};
  const float red[3] = {1, 0, 0}, green[3] = {0, 1, 0}, blue[3] = {0, 0, 1};
  // opacities 0.99995 (clamped to 0.99), 0.5, 0.99995: after the second T = 0.005, and the third
  // would take it to 5e-5 < 1e-4, so the pixel stops before it
  const float logits[3] = {10.0f, 0.0f, 10.0f};
  const float* colors[3] = {red, green, blue};
  const int p = 16 * 32 + 16;
  for (const bool far_first : {false, true}) {
    GaussianMap g;
    for (int k = 0; k < 3; ++k) {
      const int i = far_first ? 2 - k : k;
      const float m[3] = {0, 0, 1.0f + static_cast<float>(i)};
      g.push_back(m, ls, q, logits[i], colors[i]);
    }
    for (const bool simd : {false, true}) {
      const RenderResult<float> r = render_with(g, cam, simd);
      SCOPED_TRACE(testing::Message() << "far first " << far_first << " simd " << simd);
      EXPECT_NEAR(r.color[3 * p], 0.99, 1e-6);
      EXPECT_NEAR(r.color[3 * p + 1], 0.01 * 0.5, 1e-6);
      EXPECT_EQ(r.color[3 * p + 2], 0.0f);
      EXPECT_EQ(r.n_contrib[p], 2);
      EXPECT_NEAR(r.final_T[p], 0.005, 1e-7);
      EXPECT_NEAR(r.depth[p], 0.99 * 1.0 + 0.005 * 2.0, 1e-6);
    }
  }
}

// Gaussians at the same depth blend in id order, by the scalar and the AVX2 kernels.
TEST(MappingRender, GaussiansAtOneDepthBlendInIdOrder) {
  const RenderCamera cam = identity_camera(32, 32, 50, 16, 16);
  const float ls[3] = {-1.0f, -1.0f, -1.0f}, q[4] = {1, 0, 0, 0};
  const float red[3] = {1, 0, 0}, green[3] = {0, 1, 0};
  const int p = 16 * 32 + 16;
  GaussianMap tie;
  const float m[3] = {0, 0, 1.0f};
  tie.push_back(m, ls, q, 0.0f, green);
  tie.push_back(m, ls, q, 0.0f, red);
  for (const bool simd : {false, true}) {
    const RenderResult<float> r = render_with(tie, cam, simd);
    EXPECT_NEAR(r.color[3 * p + 1], 0.5, 1e-6) << "simd " << simd;  // id 0 in front
    EXPECT_NEAR(r.color[3 * p], 0.25, 1e-6);
  }
}

// The tile sort against std::sort on whole keys, for lists in id order with many equal depths,
// on both sides of the insertion-sort bound and with bytes that every key shares.
TEST(MappingRender, DepthKeySortIsStdSortOfIdOrderedKeys) {
  std::mt19937 rng(7);
  for (const std::size_t n : {0u, 1u, 2u, 47u, 48u, 49u, 300u, 5000u}) {
    for (const int depths : {3, 1000}) {
      std::uniform_int_distribution<int> pick(0, depths - 1);
      std::vector<std::uint64_t> keys(n), scratch(n);
      for (std::size_t i = 0; i < n; ++i) {
        const float depth_m = 0.5f + 0.01f * static_cast<float>(pick(rng));
        keys[i] = (std::uint64_t{std::bit_cast<std::uint32_t>(depth_m)} << 32) | i;
      }
      std::vector<std::uint64_t> expected = keys;
      std::sort(expected.begin(), expected.end());
      sort_depth_keys(keys.data(), scratch.data(), n);
      ASSERT_EQ(keys, expected) << n << " keys, " << depths << " depths";
    }
  }
}

// Tiles are claimed by whichever thread is free, and each Gaussian's gradient is summed over
// its tiles in its own order: any team size, and any claim order, gives the same bits.
TEST(MappingRender, AnyTeamSizeGivesBitIdenticalImagesAndGradients) {
  const RenderCamera cam = test::small_camera(100, 70, 80.0);
  const GaussianMap g = test::random_gaussians<float>(300, 21, 0.1, 0.9);
  for (const bool simd : {false, true}) {
    RasterSettings rs;
    rs.use_simd = simd;
    Rasterizer<float> one(rs);
    RenderResult<float> a;
    one.forward(g, cam, a);
    const test::PixelGradients seed(a.depth.size());
    GaussianMap ga;
    one.backward(g, cam, a, seed.color.data(), seed.depth.data(), seed.alpha.data(), ga);
    for (const int members : {2, 3}) {
      rt::WorkerTeam pool(members);
      Rasterizer<float> many(rs, &pool);
      for (int round = 0; round < 3; ++round) {  // claim orders differ from round to round
        RenderResult<float> b;
        many.forward(g, cam, b);
        ASSERT_EQ(a.color, b.color) << members;
        ASSERT_EQ(a.depth, b.depth) << members;
        ASSERT_EQ(a.final_T, b.final_T) << members;
        GaussianMap gb;
        many.backward(g, cam, b, seed.color.data(), seed.depth.data(), seed.alpha.data(), gb);
        ASSERT_EQ(ga.mean_w, gb.mean_w) << members << " simd " << simd;
        ASSERT_EQ(ga.log_scale, gb.log_scale) << members;
        ASSERT_EQ(ga.quat_wxyz, gb.quat_wxyz) << members;
        ASSERT_EQ(ga.opacity_logit, gb.opacity_logit) << members;
        ASSERT_EQ(ga.color_rgb, gb.color_rgb) << members;
      }
    }
  }
}

// The binning sums pairs in 64 bits and refuses a view with more than kMaxTilePairs of them
// (int offsets) before it allocates or counts any: a clear error naming the counts.
TEST(MappingRender, AViewWithTooManyTilePairsIsAClearError) {
  const RenderCamera cam = test::small_camera(4096, 4096, 3000.0);  // 65,536 tiles
  // Gaussians of 10 m deviation, 2-3 m away: each covers every tile
  const GaussianMap g = test::random_gaussians<float>(4200, 5, 0.9, 0.95, 2.3, 2.4);
  rt::WorkerTeam pool(2);
  Rasterizer<float> ras(RasterSettings{}, &pool);
  RenderResult<float> r;
  try {
    ras.forward(g, cam, r);
    FAIL() << "no error for " << ras.tile_pairs() << " pairs";
  } catch (const std::length_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(std::to_string(Rasterizer<float>::kMaxTilePairs)), std::string::npos)
        << what;
    EXPECT_NE(what.find("of 4200, 65536 tiles"), std::string::npos) << what;
  }
  // a share of them is fine
  const GaussianMap few = test::random_gaussians<float>(10, 5, 0.9, 0.95, 2.3, 2.4);
  ras.forward(few, cam, r);
  EXPECT_EQ(ras.tile_pairs(), std::size_t{10} * 65536);
}

/// The AVX2 kernels (use_avx512 off) or the AVX-512 ones against the scalar kernel.
void expect_simd_forward_matches_scalar(bool avx512) {
  const RenderCamera cam = test::small_camera(200, 150, 160.0);
  for (unsigned seed : {1u, 2u, 3u}) {
    const GaussianMap g = test::random_gaussians<float>(2000, seed, 0.05, 0.95, -3.5, -1.5);
    RasterSettings scalar_settings, simd_settings;
    scalar_settings.use_simd = false;
    simd_settings.use_avx512 = avx512;
    Rasterizer<float> scalar(scalar_settings), simd(simd_settings);
    RenderResult<float> a, b;
    scalar.forward(g, cam, a);
    simd.forward(g, cam, b);
    ASSERT_TRUE(simd.used_simd());
    ASSERT_EQ(simd.used_avx512(), avx512);
    ASSERT_FALSE(scalar.used_simd());
    float worst = 0;
    for (std::size_t i = 0; i < a.color.size(); ++i)
      worst = std::max(worst, std::abs(a.color[i] - b.color[i]));
    for (std::size_t i = 0; i < a.depth.size(); ++i)
      worst = std::max(worst, std::abs(a.depth[i] - b.depth[i]) / 10.0f);
    for (std::size_t i = 0; i < a.final_T.size(); ++i)
      worst = std::max(worst, std::abs(a.final_T[i] - b.final_T[i]));
    EXPECT_LT(worst, 1e-5f) << "seed " << seed;
    EXPECT_EQ(a.n_contrib, b.n_contrib);
  }
}

TEST(MappingRender, SimdKernelMatchesScalarWithin1e5) {
  if (!avx2_kernel_available()) GTEST_SKIP() << "no AVX2 kernel on this CPU/architecture";
  expect_simd_forward_matches_scalar(false);
}

TEST(MappingRender, Avx512KernelMatchesScalarWithin1e5) {
  if (!avx512_kernel_available()) GTEST_SKIP() << "no AVX-512 kernel on this CPU/architecture";
  expect_simd_forward_matches_scalar(true);
}

}  // namespace
}  // namespace vigs::mapping

namespace vigs::mapping {
namespace {

void expect_simd_backward_matches_scalar(bool avx512) {
  const RenderCamera cam = test::small_camera(200, 150, 160.0);
  const GaussianMap g = test::random_gaussians<float>(1500, 4, 0.05, 0.95, -3.5, -1.5);
  RasterSettings scalar_settings;
  RasterSettings simd_settings;
  scalar_settings.use_simd = false;
  simd_settings.use_avx512 = avx512;
  Rasterizer<float> scalar(scalar_settings), simd(simd_settings);
  RenderResult<float> a, b;
  scalar.forward(g, cam, a);
  simd.forward(g, cam, b);
  ASSERT_EQ(a.n_contrib, b.n_contrib);
  ASSERT_EQ(simd.used_avx512(), avx512);
  const test::PixelGradients seed(a.depth.size());
  GaussianMap ga, gb;
  scalar.backward(g, cam, a, seed.color.data(), seed.depth.data(), seed.alpha.data(), ga);
  simd.backward(g, cam, b, seed.color.data(), seed.depth.data(), seed.alpha.data(), gb);
  auto check = [](const std::vector<float>& x, const std::vector<float>& y, const char* name) {
    float scale = 0;
    for (float v : x) scale = std::max(scale, std::abs(v));
    for (std::size_t i = 0; i < x.size(); ++i)
      ASSERT_NEAR(x[i], y[i], 1e-4f * scale + 1e-7f) << name << "[" << i << "]";
  };
  check(ga.mean_w, gb.mean_w, "mean");
  check(ga.log_scale, gb.log_scale, "log_scale");
  check(ga.quat_wxyz, gb.quat_wxyz, "quat");
  check(ga.opacity_logit, gb.opacity_logit, "opacity");
  check(ga.color_rgb, gb.color_rgb, "color");
}

TEST(MappingRender, SimdBackwardMatchesScalarGradients) {
  if (!avx2_kernel_available()) GTEST_SKIP() << "no AVX2 kernel on this CPU/architecture";
  expect_simd_backward_matches_scalar(false);
}

TEST(MappingRender, Avx512BackwardMatchesScalarGradients) {
  if (!avx512_kernel_available()) GTEST_SKIP() << "no AVX-512 kernel on this CPU/architecture";
  expect_simd_backward_matches_scalar(true);
}

}  // namespace
}  // namespace vigs::mapping
