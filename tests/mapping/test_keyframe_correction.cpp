// Moving the map with its keyframes (keyframe_correction.hpp): a rigid correction of a
// keyframe moves exactly its Gaussians, and a map moved together with the camera renders the
// same image as before, so nothing but the pose changed.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "mapping/keyframe_correction.hpp"
#include "mapping/rasterizer.hpp"

namespace vigs::mapping {
namespace {

constexpr int kW = 64, kH = 48;

RenderCamera camera_at(const Eigen::Isometry3d& T_w_c) {
  const PinholeCamera k{kW, kH, 50.0, 50.0, 31.5, 23.5};
  return RenderCamera::from(k, T_w_c);
}

/// 300 random Gaussians 1.5-3 m in front of the identity camera; anchors 0, 1, 2 in turn.
GaussianMap random_map(std::vector<std::uint32_t>& anchor) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  GaussianMap map;
  anchor.clear();
  for (int i = 0; i < 300; ++i) {
    const float mean[3] = {0.8f * u(rng), 0.6f * u(rng), 2.25f + 0.75f * u(rng)};
    const float ls[3] = {std::log(0.05f + 0.03f * u(rng)), std::log(0.04f), std::log(0.01f)};
    const float q[4] = {1.0f + 0.3f * u(rng), 0.3f * u(rng), 0.3f * u(rng), 0.3f * u(rng)};
    const float rgb[3] = {0.5f + 0.4f * u(rng), 0.5f + 0.4f * u(rng), 0.5f + 0.4f * u(rng)};
    map.push_back(mean, ls, q, 1.0f, rgb);
    anchor.push_back(static_cast<std::uint32_t>(i % 3));
  }
  return map;
}

Eigen::Isometry3d correction() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.08, Eigen::Vector3d(0.2, 1.0, 0.3).normalized()).matrix();
  T.translation() = Eigen::Vector3d(0.15, -0.05, 0.2);
  return T;
}

TEST(KeyframeCorrection, MovesOnlyTheGaussiansOfTheCorrectedKeyframe) {
  std::vector<std::uint32_t> anchor;
  GaussianMap map = random_map(anchor);
  const GaussianMap before = map;
  const Eigen::Isometry3d T = correction();
  EXPECT_EQ(move_anchored(map, anchor, {{1, T}}), 100u);
  for (std::size_t i = 0; i < map.size(); ++i) {
    const Eigen::Vector3d p0(before.mean_w[3 * i], before.mean_w[3 * i + 1],
                             before.mean_w[3 * i + 2]);
    const Eigen::Vector3d p(map.mean_w[3 * i], map.mean_w[3 * i + 1], map.mean_w[3 * i + 2]);
    const Eigen::Vector3d expected = anchor[i] == 1 ? Eigen::Vector3d(T * p0) : p0;
    EXPECT_LT((p - expected).norm(), 1e-5) << i;
    if (anchor[i] != 1) {
      for (int k = 0; k < 4; ++k) EXPECT_EQ(map.quat_wxyz[4 * i + k], before.quat_wxyz[4 * i + k]);
    }
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(map.log_scale[3 * i + k], before.log_scale[3 * i + k]);
      EXPECT_EQ(map.color_rgb[3 * i + k], before.color_rgb[3 * i + k]);
    }
    EXPECT_EQ(map.opacity_logit[i], before.opacity_logit[i]);
  }
  EXPECT_EQ(move_anchored(map, anchor, {}), 0u);
  EXPECT_EQ(move_anchored(map, anchor, {{7, T}}), 0u);  // no Gaussian of keyframe 7
  anchor.pop_back();
  EXPECT_THROW(move_anchored(map, anchor, {{1, T}}), std::invalid_argument);
}

// Map and camera moved by the same correction: the same image (means, rotations and the view
// all follow one rigid motion, so every projected Gaussian is unchanged).
TEST(KeyframeCorrection, AMapMovedWithItsViewRendersTheSameImage) {
  std::vector<std::uint32_t> anchor;
  GaussianMap map = random_map(anchor);
  Rasterizer<float> raster;
  const Eigen::Isometry3d T_w_c =
      Eigen::Translation3d(0.1, 0.0, -0.2) * Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY());
  RenderCamera cam = camera_at(T_w_c);
  RenderResult<float> a, b;
  raster.forward(map, cam, a);
  const Eigen::Isometry3d T = correction();
  ASSERT_EQ(move_anchored(map, anchor, {{0, T}, {1, T}, {2, T}}), map.size());
  move_camera(cam, T);
  const RenderCamera expected = camera_at(T * T_w_c);
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(cam.R_c_w[k], expected.R_c_w[k], 1e-12);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(cam.t_c_w[k], expected.t_c_w[k], 1e-12);
  raster.forward(map, cam, b);
  double max_diff = 0.0, sum = 0.0;
  for (std::size_t p = 0; p < a.color.size(); ++p) {
    max_diff = std::max(max_diff, static_cast<double>(std::abs(a.color[p] - b.color[p])));
    sum += a.color[p];
  }
  EXPECT_GT(sum, 0.1 * static_cast<double>(a.color.size()));  // the Gaussians are in view
  EXPECT_LT(max_diff, 2e-4);
  // Moving the map alone changes the image: the check above can fail.
  ASSERT_EQ(move_anchored(map, anchor, {{0, T}, {1, T}, {2, T}}), map.size());
  raster.forward(map, cam, b);
  max_diff = 0.0;
  for (std::size_t p = 0; p < a.color.size(); ++p)
    max_diff = std::max(max_diff, static_cast<double>(std::abs(a.color[p] - b.color[p])));
  EXPECT_GT(max_diff, 0.1);
}

}  // namespace
}  // namespace vigs::mapping
