// The half-resolution training view (mapping/half_res_view.hpp): its camera keeps pixel centres
// where the full view's 2x2 blocks have theirs (a render at half resolution is the full render
// box-averaged), colour is the block mean, depth the block's near surface, masks propagate; the
// low-pass filter blurs as much of the scene at both resolutions.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "mapping/half_res_view.hpp"
#include "mapping/rasterizer.hpp"
#include "test_scene.hpp"

namespace vigs::mapping {
namespace {

TEST(HalfResView, CameraPutsAPointAtTheCentreOfItsFullResolutionBlock) {
  const RenderCamera full = test::small_camera(64, 48, 60.0);
  const RenderCamera half = half_res_camera(full);
  EXPECT_EQ(half.width_px, 32);
  EXPECT_EQ(half.height_px, 24);
  for (const Eigen::Vector3d& p_c :
       {Eigen::Vector3d(0.1, -0.2, 2.0), Eigen::Vector3d(-0.3, 0.25, 3.5)}) {
    const double u = full.fx_px * p_c.x() / p_c.z() + full.cx_px;
    const double v = full.fy_px * p_c.y() / p_c.z() + full.cy_px;
    const double uh = half.fx_px * p_c.x() / p_c.z() + half.cx_px;
    const double vh = half.fy_px * p_c.y() / p_c.z() + half.cy_px;
    // half pixel j covers full pixels 2j and 2j + 1 (centre 2j + 0.5)
    EXPECT_NEAR(2.0 * uh + 0.5, u, 1e-9);
    EXPECT_NEAR(2.0 * vh + 0.5, v, 1e-9);
  }
  for (int i = 0; i < 9; ++i) EXPECT_EQ(half.R_c_w[i], full.R_c_w[i]);
}

TEST(HalfResView, RenderAtHalfResolutionIsTheFullRenderBoxAveraged) {
  // Large smooth Gaussians: a render at half resolution must match the full render's 2x2
  // means; a principal point off by a quarter pixel moves every edge and fails this.
  const GaussianMap g = test::random_gaussians<float>(40, 5, 0.5, 0.9, -2.0, -1.4);
  const RenderCamera full = test::small_camera(128, 96, 110.0);
  Rasterizer<float> ras;
  RenderResult<float> r_full, r_half;
  ras.forward(g, full, r_full);
  HalfResView view;
  make_half_res_view(full, r_full.color.data(), nullptr, view);
  EXPECT_TRUE(view.depth_m.empty());
  ras.forward(g, view.camera, r_half);
  ASSERT_EQ(r_half.color.size(), view.rgb.size());
  double se = 0.0, se_shifted = 0.0;
  RenderCamera shifted = view.camera;
  shifted.cx_px += 0.25;
  RenderResult<float> r_shift;
  ras.forward(g, shifted, r_shift);
  for (std::size_t i = 0; i < view.rgb.size(); ++i) {
    se += std::pow(r_half.color[i] - view.rgb[i], 2);
    se_shifted += std::pow(r_shift.color[i] - view.rgb[i], 2);
  }
  const double psnr = -10.0 * std::log10(se / static_cast<double>(view.rgb.size()));
  const double psnr_shifted = -10.0 * std::log10(se_shifted / static_cast<double>(view.rgb.size()));
  std::printf("half render vs box-averaged full: %.1f dB (principal point +0.25 px: %.1f dB)\n",
              psnr, psnr_shifted);
  EXPECT_GT(psnr, 50.0);  // cx / 2 instead of (cx - 0.5) / 2 gives about 44 dB
  EXPECT_GT(psnr, psnr_shifted + 3.0);
}

/// Sum of a render's opacity over its pixels, in pixels^2 of the sensor's camera (each of the
/// render's pixels covers cam.pixel_size^2 of them).
double covered_sensor_px2(const RenderResult<float>& r, const RenderCamera& cam) {
  double sum = 0.0;
  for (int p = 0; p < r.width * r.height; ++p) sum += r.alpha(p);
  return sum * cam.pixel_size * cam.pixel_size;
}

TEST(HalfResView, AGaussianCoversTheSameAreaOfTheSceneAtHalfResolution) {
  // One Gaussian of about a pixel (standard deviation 1 px at full resolution) alone in view:
  // its accumulated opacity summed over the image is o 2 pi sqrt(det(Sigma_2D + lowpass I)), in
  // the render's pixels^2. The low-pass filter blurs by 0.3 sensor px^2 at both resolutions,
  // so in sensor pixels the two areas agree; with 0.3 half-resolution px^2 (1.2 sensor px^2,
  // what the coarse iterations used before) the half render covers 30 % more, and a Gaussian
  // fitted there shrinks at full resolution.
  const RenderCamera full = test::small_camera(64, 48, 60.0);
  const RenderCamera half = half_res_camera(full);
  EXPECT_DOUBLE_EQ(half.pixel_size, 2.0);
  EXPECT_DOUBLE_EQ(half.lowpass_px2(0.3), 0.075);
  const double s_m = 2.0 / 60.0;  // 1 px at 2 m
  const Eigen::Vector3d p_w = full.T_w_c() * Eigen::Vector3d(0.03, -0.02, 2.0);
  GaussianMap g;
  g.resize(1);
  for (int k = 0; k < 3; ++k) {
    g.mean_w[k] = static_cast<float>(p_w[k]);
    g.log_scale[k] = static_cast<float>(std::log(s_m));
    g.color_rgb[k] = 1.0f;
  }
  g.quat_wxyz = {1.0f, 0.0f, 0.0f, 0.0f};
  g.opacity_logit[0] = std::log(0.2f / 0.8f);  // 0.2: no alpha clamp at the centre
  Rasterizer<float> ras;
  RenderResult<float> r_full, r_half;
  ras.forward(g, full, r_full);
  ras.forward(g, half, r_half);
  const double a_full = covered_sensor_px2(r_full, full);
  const double a_half = covered_sensor_px2(r_half, half);
  std::printf("covered: %.3f sensor px^2 at full resolution, %.3f at half\n", a_full, a_half);
  EXPECT_GT(a_full, 1.0);
  EXPECT_NEAR(a_half / a_full, 1.0, 0.03);
}

TEST(HalfResView, ColourIsTheBlockMeanDepthTheNearSurfaceMasksPropagate) {
  RenderCamera full;
  full.width_px = 5;  // the odd last column is dropped
  full.height_px = 2;
  full.fx_px = full.fy_px = 10.0;
  std::vector<float> rgb(3 * 10, 0.0f);
  for (int p = 0; p < 10; ++p) rgb[3 * p] = 0.1f * static_cast<float>(p);
  // blocks: (near surface 2.0, 2.04 and an edge pixel at 3.0), (missing, 1.0),
  const std::vector<float> depth = {2.0f, 2.04f, 0.0f, 1.0f, 9.0f,  //
                                    3.0f, 2.02f, 0.0f, 0.0f, 9.0f};
  HalfResView v;
  make_half_res_view(full, rgb.data(), depth.data(), v);
  ASSERT_EQ(v.camera.width_px, 2);
  ASSERT_EQ(v.camera.height_px, 1);
  EXPECT_FLOAT_EQ(v.rgb[0], 0.25f * (0.0f + 0.1f + 0.5f + 0.6f));
  EXPECT_FLOAT_EQ(v.rgb[3], 0.25f * (0.2f + 0.3f + 0.7f + 0.8f));
  EXPECT_FLOAT_EQ(v.depth_m[0], (2.0f + 2.04f + 2.02f) / 3.0f);  // 3.0 is another surface
  EXPECT_FLOAT_EQ(v.depth_m[1], 1.0f);                           // only the valid pixel
  std::vector<float> none(10, 0.0f);
  make_half_res_view(full, rgb.data(), none.data(), v);
  EXPECT_EQ(v.depth_m[0], 0.0f);
  std::vector<float> moving = depth;
  moving[6] = -1.0f;
  make_half_res_view(full, rgb.data(), moving.data(), v);
  EXPECT_EQ(v.depth_m[0], -1.0f);  // a moving pixel masks its block
  EXPECT_FLOAT_EQ(v.depth_m[1], 1.0f);
}

}  // namespace
}  // namespace vigs::mapping
