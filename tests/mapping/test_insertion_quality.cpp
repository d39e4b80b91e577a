// Insertion alone must render the keyframe's own view: a simulated office frame (the
// 720x480 / stride 4 sample angle at half the resolution) is inserted into an empty map and
// rendered from the same pose, with no optimisation step. The GS-ICP SLAM rule (flat opacity
// 0.1, scales divided by 2 z^1.5) is the baseline that renders the view almost black.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/config/robot_config.hpp"
#include "mapping/far_field.hpp"
#include "mapping/insertion.hpp"
#include "mapping/insertion_gate.hpp"
#include "mapping/rasterizer.hpp"
#include "mapping/rgbd_keyframe.hpp"
#include "office_frames.hpp"
#include "sim/simulator.hpp"

namespace vigs::mapping {
namespace {

using test::Psnr;
using test::psnr_of;

class InsertionQuality : public ::testing::Test {
 protected:
  void SetUp() override {
    cfg_ = test::half_res_office(6.0);
    sim_ = std::make_unique<sim::Simulator>(cfg_);
    sim_->render_at(4.0, 80, frame_);
    T_w_c_ = sim_->camera_pose(4.0);
    rgb_ = ImageU8(frame_.width, frame_.height, 3);
    rgb_.data = frame_.color;
    depth_ = ImageF32(frame_.width, frame_.height, 1);
    depth_.data = frame_.depth_m;
  }

  /// Inserts the frame (stride 2) with `s` and renders it from its own pose.
  Psnr inserted_psnr(const InsertSettings& s, bool footprint, std::size_t* gaussians) {
    const PinholeCamera cam = PinholeCamera::from_settings(cfg_.camera);
    RgbdSampling sampling;
    sampling.stride_px = 2;
    KeyframeGaussians kf = keyframe_from_rgbd(cam, rgb_, depth_, T_w_c_, sampling);
    if (!footprint) kf.sample_angle_rad = 0.0;
    GaussianMap map;
    GaussianInserter ins(s);
    *gaussians = ins.insert(map, kf);
    Rasterizer<float> ras;
    RenderResult<float> r;
    ras.forward(map, RenderCamera::from(cam, T_w_c_), r);
    return psnr_of(r, frame_);
  }

  config::RobotConfig cfg_;
  std::unique_ptr<sim::Simulator> sim_;
  sim::RgbdFrame frame_;
  geometry::Pose T_w_c_;
  ImageU8 rgb_;
  ImageF32 depth_;
};

TEST_F(InsertionQuality, NewGaussiansRenderTheirOwnViewBeforeAnyIteration) {
  std::size_t n_new = 0, n_old = 0;
  const Psnr now = inserted_psnr(InsertSettings{}, true, &n_new);
  InsertSettings gsicp;
  gsicp.opacity = 0.1;
  const Psnr old = inserted_psnr(gsicp, false, &n_old);
  std::printf(
      "insertion only, own view 360x240: footprint rule %.2f dB whole / %.2f dB valid depth "
      "(%zu Gaussians); GS-ICP rule %.2f / %.2f dB (%zu)\n",
      now.whole_db, now.valid_depth_db, n_new, old.whole_db, old.valid_depth_db, n_old);
  EXPECT_EQ(n_new, n_old);  // same points, only scale and opacity differ
  // measured 23.5 dB (the goal is 24 dB); the GS-ICP rule gives 5.3 dB
  EXPECT_GT(now.valid_depth_db, 22.0);
  EXPECT_GT(now.valid_depth_db, old.valid_depth_db + 10.0);
}

TEST_F(InsertionQuality, ARevisitAddsFewGaussiansWhereTheMapAlreadyRendersTheView) {
  const PinholeCamera cam = PinholeCamera::from_settings(cfg_.camera);
  RgbdSampling sampling;
  sampling.stride_px = 2;
  GaussianMap map;
  GaussianInserter ins;
  ins.insert(map, keyframe_from_rgbd(cam, rgb_, depth_, T_w_c_, sampling));
  const std::size_t first = map.size();
  // the same corridor 0.1 s later (a few centimetres on), with new sensor noise
  sim::RgbdFrame f2;
  sim_->render_at(4.1, 82, f2);
  const geometry::Pose T2 = sim_->camera_pose(4.1);
  ImageU8 rgb2(f2.width, f2.height, 3);
  rgb2.data = f2.color;
  ImageF32 depth2(f2.width, f2.height, 1);
  depth2.data = f2.depth_m;
  const KeyframeGaussians kf2 = keyframe_from_rgbd(cam, rgb2, depth2, T2, sampling);
  // voxel occupancy alone
  GaussianMap map_voxel = map;
  GaussianInserter ins_voxel = ins;
  const std::size_t added_voxel = ins_voxel.insert(map_voxel, kf2);
  // gated by the render of the new view
  const RenderCamera cam2 = RenderCamera::from(cam, T2);
  Rasterizer<float> ras;
  RenderResult<float> r;
  ras.forward(map, cam2, r);
  std::vector<char> keep;
  gate_points(kf2, cam2, r, GateSettings{}, keep);
  const std::size_t added = ins.insert(map, kf2, &keep);
  std::printf(
      "revisit: %zu Gaussians, then +%zu gated (%.2f %%), +%zu with voxels only (%.2f %%)\n", first,
      added, 100.0 * static_cast<double>(added) / static_cast<double>(first), added_voxel,
      100.0 * static_cast<double>(added_voxel) / static_cast<double>(first));
  EXPECT_LT(static_cast<double>(added), 0.05 * static_cast<double>(first));
  EXPECT_LT(2 * added, added_voxel);
}

}  // namespace
}  // namespace vigs::mapping

namespace vigs::mapping {
namespace {

/// The frame's far field (far_field.hpp) inserted after its points, as the mapper does.
std::size_t insert_far(GaussianMap& map, const RenderCamera& cam, const sim::RgbdFrame& f,
                       const RenderResult<float>* render, const FarFieldSettings& s,
                       std::vector<float>& rgb) {
  rgb.resize(f.color.size());
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = f.color[i] / 255.0f;
  const InsertSettings ins;
  return insert_far_field(map, {cam, rgb.data(), f.depth_m.data()}, render, s, ins.cover,
                          ins.opacity, GateSettings{}.max_alpha, 0.45);
}

TEST_F(InsertionQuality, TheFarFieldRendersWhatHasNoDepthInsteadOfBlack) {
  const PinholeCamera cam = PinholeCamera::from_settings(cfg_.camera);
  const RenderCamera rcam = RenderCamera::from(cam, T_w_c_);
  RgbdSampling sampling;
  sampling.stride_px = 2;
  std::size_t no_depth = 0;
  for (const float z : frame_.depth_m) no_depth += z > 0.0f ? 0 : 1;
  auto render_psnr = [&](const FarFieldSettings& far, std::size_t* n_far) {
    GaussianMap map;
    GaussianInserter ins;
    ins.insert(map, keyframe_from_rgbd(cam, rgb_, depth_, T_w_c_, sampling));
    std::vector<float> rgb;
    *n_far = insert_far(map, rcam, frame_, nullptr, far, rgb);
    Rasterizer<float> ras;
    RenderResult<float> r;
    ras.forward(map, rcam, r);
    return psnr_of(r, frame_);
  };
  FarFieldSettings far;
  far.stride_px = 4;  // the default 8 px at 720x480, at this half resolution
  FarFieldSettings off = far;
  off.depth_m = 0.0;
  std::size_t n_on = 0, n_off = 0;
  const Psnr with = render_psnr(far, &n_on);
  const Psnr without = render_psnr(off, &n_off);
  std::printf(
      "far field, own view 360x240 (%.1f %% of pixels without depth): %.2f dB whole / %.2f dB "
      "valid depth with %zu far Gaussians; %.2f / %.2f dB without\n",
      100.0 * static_cast<double>(no_depth) / static_cast<double>(frame_.depth_m.size()),
      with.whole_db, with.valid_depth_db, n_on, without.whole_db, without.valid_depth_db);
  ASSERT_GT(no_depth, frame_.depth_m.size() / 50);  // the frame has a far part
  EXPECT_EQ(n_off, 0u);
  EXPECT_GT(with.whole_db, 23.0);  // measured 24.5 dB, 16.8 dB without
  EXPECT_LT(without.whole_db, 23.0);
  // the far Gaussians stay behind what has depth
  EXPECT_GT(with.valid_depth_db, without.valid_depth_db - 0.3);
}

TEST_F(InsertionQuality, ARevisitAddsFewFarGaussians) {
  const PinholeCamera cam = PinholeCamera::from_settings(cfg_.camera);
  RgbdSampling sampling;
  sampling.stride_px = 2;
  FarFieldSettings far;
  far.stride_px = 4;
  GaussianMap map;
  GaussianInserter ins;
  std::vector<float> rgb;
  ins.insert(map, keyframe_from_rgbd(cam, rgb_, depth_, T_w_c_, sampling));
  const std::size_t first =
      insert_far(map, RenderCamera::from(cam, T_w_c_), frame_, nullptr, far, rgb);
  // the same corridor 0.1 s later: gated by the render of the map from the new camera
  sim::RgbdFrame f2;
  sim_->render_at(4.1, 82, f2);
  const RenderCamera cam2 = RenderCamera::from(cam, sim_->camera_pose(4.1));
  Rasterizer<float> ras;
  RenderResult<float> r;
  ras.forward(map, cam2, r);
  GaussianMap gated = map, ungated = map;
  const std::size_t added = insert_far(gated, cam2, f2, &r, far, rgb);
  const std::size_t added_ungated = insert_far(ungated, cam2, f2, nullptr, far, rgb);
  std::printf("far field revisit: %zu far Gaussians, then +%zu gated (%.2f %%), +%zu ungated\n",
              first, added, 100.0 * static_cast<double>(added) / static_cast<double>(first),
              added_ungated);
  ASSERT_GT(first, 100u);
  EXPECT_LT(static_cast<double>(added), 0.05 * static_cast<double>(first));
  EXPECT_GT(added_ungated, first / 2);
}

}  // namespace
}  // namespace vigs::mapping
