// PLY export/import, keyframe insertion (rotation, scale normalisation, voxel occupancy) and
// pruning.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "../common/temp_files.hpp"
#include "mapping/compact_kept.hpp"
#include "mapping/insertion.hpp"
#include "mapping/map_optimizer.hpp"
#include "mapping/ply_io.hpp"
#include "pipeline/tracking_keyframe.hpp"
#include "test_scene.hpp"

namespace vigs::mapping {
namespace {

// Removed when the test program exits, passed or failed.
std::string temp_path(const std::string& name) {
  static vigs::test::TempFiles files("vigs_mapping");
  return files.path(name);
}

TEST(MappingPly, RoundTripIsExact) {
  const GaussianMap g = test::random_gaussians<float>(50, 4);
  const std::string path = temp_path("roundtrip.ply");
  write_gaussian_ply(path, g);
  const GaussianMap r = read_gaussian_ply(path);
  ASSERT_EQ(r.size(), g.size());
  EXPECT_EQ(r.mean_w, g.mean_w);
  EXPECT_EQ(r.log_scale, g.log_scale);
  EXPECT_EQ(r.quat_wxyz, g.quat_wxyz);
  EXPECT_EQ(r.opacity_logit, g.opacity_logit);
  for (std::size_t i = 0; i < g.color_rgb.size(); ++i)
    EXPECT_NEAR(r.color_rgb[i], g.color_rgb[i], 1e-6f);
  // header is the standard 3DGS layout
  std::ifstream f(path, std::ios::binary);
  std::string header, line;
  while (std::getline(f, line) && line != "end_header") header += line + "\n";
  EXPECT_NE(header.find("format binary_little_endian 1.0\nelement vertex 50\nproperty float x\n"),
            std::string::npos);
  EXPECT_NE(header.find("property float f_dc_0\nproperty float f_dc_1\nproperty float f_dc_2\n"
                        "property float opacity\nproperty float scale_0\n"),
            std::string::npos);
  EXPECT_NE(header.find("property float rot_3\n"), std::string::npos);
  std::remove(path.c_str());
}

// No NaN reaches a file: a Gaussian with any non-finite parameter is left out and counted,
// and the rest are written as they are (the reader refuses a non-finite value).
TEST(MappingPly, GaussiansWithNonFiniteParametersAreLeftOut) {
  GaussianMap g = test::random_gaussians<float>(8, 5);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  g.color_rgb[3 * 1 + 2] = nan;
  g.mean_w[3 * 3 + 1] = inf;
  g.quat_wxyz[4 * 4 + 3] = nan;
  g.log_scale[3 * 6] = -inf;
  g.opacity_logit[7] = nan;
  const std::string path = temp_path("nonfinite.ply");
  EXPECT_EQ(write_gaussian_ply(path, g), 5u);
  const GaussianMap r = read_gaussian_ply(path);
  ASSERT_EQ(r.size(), 3u);
  const std::size_t kept[] = {0, 2, 5};
  for (std::size_t j = 0; j < 3; ++j)
    for (std::size_t k = 0; k < 3; ++k)
      EXPECT_EQ(r.mean_w[3 * j + k], g.mean_w[3 * kept[j] + k]) << j;
  std::remove(path.c_str());
}

TEST(MappingPly, BadFilesGiveClearErrors) {
  const std::string path = temp_path("bad.ply");
  auto expect_error = [&](const std::string& content, const std::string& needle) {
    {
      std::ofstream f(path, std::ios::binary);
      f << content;
    }
    try {
      read_gaussian_ply(path);
      ADD_FAILURE() << "no error for: " << needle;
    } catch (const PlyError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  expect_error("hello\n", "missing 'ply' magic");
  expect_error("ply\nformat ascii 1.0\nend_header\n", "format 'ascii'");
  expect_error(
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
      "end_header\n",
      "missing float vertex property 'y'");
  // a valid header with a truncated body
  GaussianMap g = test::random_gaussians<float>(3, 1);
  write_gaussian_ply(path, g);
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 10);
  EXPECT_THROW(read_gaussian_ply(path), PlyError);
  try {
    read_gaussian_ply(path);
  } catch (const PlyError& e) {
    EXPECT_NE(std::string(e.what()).find("truncated at byte"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_gaussian_ply(path + ".missing"), PlyError);
  std::remove(path.c_str());
}

TEST(MappingInsertion, RotationIsProperAndScalesFollowGsIcp) {
  // covariance with known axes: std devs 0.03, 0.02, 0.001 along a rotated frame
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()) *
                             Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
  const Eigen::Vector3d sd(0.03, 0.02, 0.001);
  const Eigen::Matrix3d cov = R * sd.cwiseAbs2().asDiagonal() * R.transpose();
  Eigen::Quaterniond q;
  Eigen::Vector3d s;
  covariance_to_rotation_scale(cov, q, s);
  EXPECT_NEAR(q.toRotationMatrix().determinant(), 1.0, 1e-12);
  EXPECT_TRUE(s.isApprox(sd, 1e-9));
  const Eigen::Matrix3d back =
      q.toRotationMatrix() * s.cwiseAbs2().asDiagonal() * q.toRotationMatrix().transpose();
  EXPECT_TRUE(back.isApprox(cov, 1e-9));

  KeyframeGaussians kf;
  kf.T_w_c.translation() = Eigen::Vector3d(1, 2, 3);
  kf.T_w_c.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (double z : {0.5, 2.0}) {
    kf.points_c.emplace_back(0.1f, 0.0f, static_cast<float>(z));
    kf.covariances_c.push_back(cov.cast<float>());
    kf.colors.emplace_back(0.2f, 0.4f, 0.6f);
  }
  GaussianMap map;
  GaussianInserter ins(InsertSettings{0.02, 0.1, 1e-5});
  ASSERT_EQ(ins.insert(map, kf), 2u);
  // z = 0.5: 2 z^1.5 = 0.707 < 1 -> no division; z = 2: divide by 2 * 2^1.5 = 5.657
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(std::exp(map.log_scale[static_cast<std::size_t>(k)]), sd(k), 1e-6);
    EXPECT_NEAR(std::exp(map.log_scale[static_cast<std::size_t>(3 + k)]),
                sd(k) / (2.0 * std::pow(2.0, 1.5)), 1e-6);
  }
  EXPECT_NEAR(sigmoid(map.opacity_logit[0]), 0.1f, 1e-6f);
  const Eigen::Vector3d p_w = kf.T_w_c * Eigen::Vector3d(0.1, 0, 2.0);
  EXPECT_NEAR(map.mean_w[3], p_w.x(), 1e-6);
  // world orientation = R_w_c * R_c
  const Eigen::Quaterniond q_w(map.quat_wxyz[0], map.quat_wxyz[1], map.quat_wxyz[2],
                               map.quat_wxyz[3]);
  const Eigen::Matrix3d cov_w =
      q_w.toRotationMatrix() * sd.cwiseAbs2().asDiagonal() * q_w.toRotationMatrix().transpose();
  EXPECT_TRUE(cov_w.isApprox(kf.T_w_c.linear() * cov * kf.T_w_c.linear().transpose(), 1e-5));
  // revisiting the same place adds nothing
  EXPECT_EQ(ins.insert(map, kf), 0u);
  EXPECT_EQ(map.size(), 2u);
  GaussianInserter fresh(InsertSettings{0.02, 0.1, 1e-5});
  fresh.rebuild(map);
  EXPECT_EQ(fresh.insert(map, kf), 0u);
}

// See-through pruning removes a few Gaussians per keyframe; forget() frees just their voxels
// (no O(map) rebuild), so the keyframe's own points can fill the place at once.
TEST(MappingInsertion, ForgetFreesTheVoxelsOfRemovedGaussiansOnly) {
  KeyframeGaussians kf;
  for (int i = 0; i < 6; ++i) {
    kf.points_c.emplace_back(0.1f * static_cast<float>(i), 0.0f, 1.0f);
    kf.covariances_c.push_back(Eigen::Matrix3f::Identity() * 1e-4f);
    kf.colors.emplace_back(0.5f, 0.5f, 0.5f);
  }
  GaussianMap map;
  GaussianInserter ins(InsertSettings{0.02, 0.1, 1e-5});
  ASSERT_EQ(ins.insert(map, kf), 6u);
  ASSERT_EQ(ins.occupied_voxels(), 6u);
  const std::vector<char> keep = {1, 0, 1, 0, 1, 1};  // two condemned
  ins.forget(map, keep);
  EXPECT_EQ(ins.occupied_voxels(), 4u);
  ASSERT_EQ(map.compact(keep), 2u);
  // The same view again: exactly the two freed places are filled, nothing doubles.
  EXPECT_EQ(ins.insert(map, kf), 2u);
  EXPECT_EQ(map.size(), 6u);
  EXPECT_EQ(ins.insert(map, kf), 0u);
}

TEST(MappingPrune, RemovesTransparentAndOversizedGaussians) {
  GaussianMap g = test::random_gaussians<float>(10, 2);
  g.opacity_logit[3] = logit(0.001f);       // transparent
  g.log_scale[3 * 5 + 1] = std::log(2.0f);  // 2 m wide
  const auto keep = prune_keep_mask(g, PruneSettings{0.005, 0.5});
  EXPECT_EQ(keep[3], 0);
  EXPECT_EQ(keep[5], 0);
  const float kept_mean = g.mean_w[3 * 6];
  EXPECT_EQ(g.compact(keep), 2u);
  EXPECT_EQ(g.size(), 8u);
  EXPECT_EQ(g.mean_w[3 * 4], kept_mean);  // order preserved
}

TEST(MappingPrune, RemovesGaussiansWithAnyNonFiniteParameter) {
  GaussianMap g = test::random_gaussians<float>(6, 3);
  g.color_rgb[3 * 1 + 1] = std::numeric_limits<float>::quiet_NaN();  // what a NaN render spread
  g.quat_wxyz[4 * 2] = std::numeric_limits<float>::infinity();
  g.log_scale[3 * 4 + 2] = std::numeric_limits<float>::quiet_NaN();
  const auto keep = prune_keep_mask(g, PruneSettings{0.005, 0.5});
  EXPECT_EQ(keep, (std::vector<char>{1, 0, 0, 1, 0, 1}));
}

TEST(MappingPrune, CompactKeptMovesWholeRecordsInOrder) {
  // Records of three: 0..2 | 10..12 | 20..22 | 30..32; the second and the last are dropped.
  std::vector<int> v = {0, 1, 2, 10, 11, 12, 20, 21, 22, 30, 31, 32};
  const std::vector<char> keep = {1, 0, 1, 0};
  EXPECT_EQ(compact_kept(v, keep, 3), 2u);
  EXPECT_EQ(v, (std::vector<int>{0, 1, 2, 20, 21, 22}));
  std::vector<std::uint8_t> flags = {7, 8, 9};
  EXPECT_EQ(compact_kept(flags, std::vector<char>{0, 0, 1}), 1u);
  EXPECT_EQ(flags, (std::vector<std::uint8_t>{9}));
}

TEST(MappingInsertion, TrackerKeyframesInsertFromTheRawCovariance) {
  tracking::Keyframe kf;
  kf.T_w_c.translation() = Eigen::Vector3d(0.5, 0, 0);
  kf.cloud_c.points_m.emplace_back(0.0f, 0.0f, 0.8f);
  // raw kNN covariance (std devs 3 cm, 2 cm, 1 mm along the axes); the regularised one differs
  kf.cloud_c.cov_raw_m2.push_back(Eigen::Vector3f(9e-4f, 4e-4f, 1e-6f).asDiagonal());
  kf.cloud_c.cov_m2.push_back(Eigen::Vector3f(2.25f, 1.0f, 1e-3f).asDiagonal());
  kf.cloud_c.colors_rgb.push_back({255, 0, 51});
  const KeyframeGaussians g = pipeline::to_keyframe_gaussians(kf, 0.0);  // GS-ICP SLAM rule
  GaussianMap map;
  GaussianInserter ins(InsertSettings{0.02, 0.1, 1e-5});
  ASSERT_EQ(ins.insert(map, g), 1u);
  const double div = 2.0 * std::pow(0.8, 1.5);  // 1.43 > 1
  EXPECT_NEAR(std::exp(map.log_scale[0]), 0.03 / div, 1e-6);
  EXPECT_NEAR(std::exp(map.log_scale[1]), 0.02 / div, 1e-6);
  EXPECT_NEAR(std::exp(map.log_scale[2]), 0.001 / div, 1e-6);
  EXPECT_NEAR(map.mean_w[0], 0.5f, 1e-6f);
  EXPECT_NEAR(map.color_rgb[0], 1.0f, 1e-6f);
  EXPECT_NEAR(map.color_rgb[2], 0.2f, 1e-6f);
}

}  // namespace
}  // namespace vigs::mapping
