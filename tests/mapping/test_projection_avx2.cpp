// The float projection with the AVX2 kernels (projection_avx2.hpp: may_reach_image() per
// Gaussian, the covariance part eight at a time) must give the scalar projection's result bit
// for bit: the same Gaussians visible, the same radius, mean, conic, depth (the opacity is
// sigmoid(logit), not stored).
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "mapping/raster_simd.hpp"
#include "mapping/rasterizer.hpp"
#include "test_scene.hpp"

namespace vigs::mapping {
namespace {

std::uint32_t bits(float x) {
  return std::bit_cast<std::uint32_t>(x);
}

/// Gaussians around and behind the camera: on screen, off screen by a little and a lot, inside
/// the near plane, wider than the 1.3 x half-FOV clamp yet reaching the image, needles and
/// discs, unnormalised quaternions, faint (under min_alpha) and opaque, and a few degenerate
/// (zero quaternion, infinite and NaN entries).
GaussianMap varied_gaussians(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  GaussianMap g;
  for (int i = 0; i < n; ++i) {
    const double z = -0.5 + 6.0 * u(rng);
    const double spread = 1.8 * u(rng);  // up to ~2.5x the half field of view's tangent
    float mean[3] = {static_cast<float>((u(rng) - 0.5) * 2 * spread * z),
                     static_cast<float>((u(rng) - 0.5) * 2 * spread * z), static_cast<float>(z)};
    const double ls_base = -6.0 + 6.5 * u(rng);
    float ls[3] = {static_cast<float>(ls_base), static_cast<float>(ls_base - 3 * u(rng)),
                   static_cast<float>(ls_base - 3 * u(rng))};
    float q[4] = {static_cast<float>(2 * u(rng) - 1), static_cast<float>(2 * u(rng) - 1),
                  static_cast<float>(2 * u(rng) - 1), static_cast<float>(2 * u(rng) - 1)};
    const float logit = static_cast<float>(-8.0 + 14.0 * u(rng));
    const float rgb[3] = {0.5f, 0.5f, 0.5f};
    switch (i % 97) {
      case 0:
        q[0] = q[1] = q[2] = q[3] = 0.0f;
        break;
      case 1:
        mean[0] = std::numeric_limits<float>::quiet_NaN();
        break;
      case 2:
        ls[1] = std::numeric_limits<float>::infinity();
        break;
      case 3:
        mean[2] = 0.01f;
        break;  // at the near plane
      default:
        break;
    }
    g.push_back(mean, ls, q, logit, rgb);
  }
  return g;
}

void expect_same_projection(const GaussianMap& g, const RenderCamera& cam, int* visible_out) {
  RasterSettings scalar, lanes;
  scalar.use_simd = false;
  Rasterizer<float> rs(scalar), rl(lanes);
  RenderResult<float> a, b;
  rs.forward(g, cam, a);
  rl.forward(g, cam, b);
  int visible = 0, mismatches = 0;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const std::optional<ProjectedGaussian<float>> ps = rs.projected(i), pl = rl.projected(i);
    const int rs_px = ps ? ps->radius : 0, rl_px = pl ? pl->radius : 0;
    if (rs_px != rl_px) {
      ADD_FAILURE() << "Gaussian " << i << ": radius " << rs_px << " vs " << rl_px;
      if (++mismatches > 10) return;
      continue;
    }
    if (!ps) continue;
    ++visible;
    for (int k = 0; k < 2; ++k) EXPECT_EQ(bits(ps->mean2d[k]), bits(pl->mean2d[k])) << i;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(bits(ps->conic[k]), bits(pl->conic[k])) << i;
    EXPECT_EQ(bits(ps->depth), bits(pl->depth)) << i;
  }
  *visible_out = visible;
}

TEST(ProjectionAvx2, GivesTheScalarProjectionBitForBit) {
  if (!avx2_kernel_available()) GTEST_SKIP() << "no AVX2 kernel on this CPU/architecture";
  const GaussianMap g = varied_gaussians(20000, 5);
  int visible = 0;
  expect_same_projection(g, test::small_camera(320, 240, 250.0), &visible);
  // the scene must hold both outcomes in numbers, or the comparison shows little
  EXPECT_GT(visible, 2000);
  EXPECT_LT(visible, 15000);
  // a batch tail (n not a multiple of 8) and a single Gaussian
  GaussianMap few = varied_gaussians(13, 9);
  expect_same_projection(few, test::small_camera(320, 240, 250.0), &visible);
}

TEST(ProjectionAvx2, ClampedWideGaussiansMatchToo) {
  if (!avx2_kernel_available()) GTEST_SKIP() << "no AVX2 kernel on this CPU/architecture";
  // large Gaussians far outside the 1.3 x half-FOV clamp whose footprint still reaches the image
  GaussianMap g;
  constexpr int kClamped = 400;
  for (int i = 0; i < kClamped; ++i) {
    const float z = 1.0f + 0.01f * static_cast<float>(i);
    const float side = (i % 2 == 0 ? 1.0f : -1.0f) * (1.2f + 0.004f * static_cast<float>(i)) * z;
    const float mean[3] = {i % 4 < 2 ? side : 0.0f, i % 4 < 2 ? 0.0f : side, z};
    const float ls[3] = {-0.3f, -0.8f, -2.0f};
    const float q[4] = {1.0f, 0.1f * static_cast<float>(i % 7), 0.2f, -0.1f};
    const float rgb[3] = {0.5f, 0.5f, 0.5f};
    g.push_back(mean, ls, q, 2.0f, rgb);
  }
  int visible = 0;
  expect_same_projection(g, test::small_camera(320, 240, 250.0), &visible);
  EXPECT_GT(visible, 50) << "of " << kClamped << " clamped Gaussians";
}

/// A Gaussian at camera-frame position p_c (metres) of `cam`, in world coordinates.
void push_at_camera_point(GaussianMap& g, const RenderCamera& cam, const float p_c[3], float ls,
                          float logit) {
  float mean[3];
  for (int k = 0; k < 3; ++k) {  // p_w = R_c_w^T (p_c - t_c_w)
    double acc = 0;
    for (int r = 0; r < 3; ++r) acc += cam.R_c_w[3 * r + k] * (p_c[r] - cam.t_c_w[r]);
    mean[k] = static_cast<float>(acc);
  }
  const float scales[3] = {ls, ls - 0.5f, ls - 2.0f};
  const float q[4] = {0.9f, 0.2f, -0.1f, 0.3f};
  const float rgb[3] = {0.5f, 0.5f, 0.5f};
  g.push_back(mean, scales, q, logit, rgb);
}

// The AVX2 pass that drops Gaussians before the exact tests keeps margins; where the decision
// changes (sub-pixel steps across the image border at which a Gaussian stops being visible,
// opacity logits across min_alpha, depths across the near plane) every Gaussian must still
// come out as in the scalar loop. (A radius margin cut by 2 px is caught by the varied scene
// above, where some Gaussians' radii come within a pixel of the cull's bound.)
TEST(ProjectionAvx2, DecidesAsTheScalarCullAtItsEdges) {
  if (!avx2_kernel_available()) GTEST_SKIP() << "no AVX2 kernel on this CPU/architecture";
  const RenderCamera cam = test::small_camera(320, 240, 250.0);
  const RasterSettings rs;
  const float logit_min = static_cast<float>(std::log(rs.min_alpha / (1.0 - rs.min_alpha)));
  GaussianMap border, faint, near;
  for (int i = 0; i < 2000; ++i) {
    const float z = 2.0f;
    const float u = -40.0f + 0.02f * static_cast<float>(i);  // left of the image, to its edge
    const float p_left[3] = {
        (u - static_cast<float>(cam.cx_px)) * z / static_cast<float>(cam.fx_px), 0.1f, z};
    push_at_camera_point(border, cam, p_left, -3.0f, 2.0f);
    const float p_mid[3] = {0.05f, -0.02f, 1.5f};
    push_at_camera_point(faint, cam, p_mid, -3.0f,
                         logit_min - 0.1f + 1e-4f * static_cast<float>(i));
    const float p_near[3] = {0.0f, 0.0f, 0.005f + 1e-5f * static_cast<float>(i)};
    push_at_camera_point(near, cam, p_near, -6.0f, 2.0f);
  }
  for (const GaussianMap* g : {&border, &faint, &near}) {
    int visible = 0;
    expect_same_projection(*g, cam, &visible);
    EXPECT_GT(visible, 50);  // both outcomes, many of each
    EXPECT_LT(visible, 1950);
  }
}

}  // namespace
}  // namespace vigs::mapping
