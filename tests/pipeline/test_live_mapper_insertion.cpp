// The live mapper inserts a keyframe's points with the footprint rule (mapping/insertion.hpp):
// each Gaussian's in-plane standard deviations cover the patch its sample stands for at the
// tracker's pixel stride. It once passed no sample angle and inserted every real-time keyframe
// with GS-ICP SLAM's scales (a speckled map: 15 dB held-out over three minutes, where the
// lockstep replay's insertion alone gives about 24).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "pipeline/keyframe_handoff.hpp"
#include "pipeline/live_mapper.hpp"
#include "pipeline/tracking_keyframe.hpp"

namespace vigs::pipeline {
namespace {

constexpr int kW = 64, kH = 48;
const PinholeCamera kCamera{kW, kH, 60.0, 60.0, 31.5, 23.5};

/// The keyframe's own points only, as they were inserted: no far field, no see-through
/// pruning, no moving mask, no iteration.
config::MappingSettings insertion_only_settings() {
  config::MappingSettings s;
  s.far_field.depth_m = 0.0;
  s.see_through.enabled = false;
  s.moving_mask.enabled = false;
  s.iterations_per_tick = 0;
  s.threads = 1;
  return s;
}

/// A sample of a wall 2 m ahead at pixel (u, v) of kCamera, with a flat kNN covariance.
void add_wall_sample(tracking::Keyframe& kf, int u, int v, std::uint8_t grey) {
  const float z = 2.0f;
  kf.cloud_c.points_m.emplace_back((u - 31.5f) * z / 60.0f, (v - 23.5f) * z / 60.0f, z);
  kf.cloud_c.cov_raw_m2.push_back(Eigen::Vector3f(1e-3f, 1e-3f, 1e-7f).asDiagonal());
  kf.cloud_c.cov_m2.push_back(Eigen::Matrix3f::Identity());
  kf.cloud_c.colors_rgb.push_back({grey, grey, grey});
}

/// A live mapper on kCamera (tracker stride 4) with insertion_only_settings().
class LiveMapperInsertion : public ::testing::Test {
 protected:
  static constexpr int stride = 4;
  const config::MappingSettings s = insertion_only_settings();
  rt::FramePool pool{rt::FramePoolSettings{4, kW, kH, 3}};
  KeyframeHandoff handoff{2, 1024};
  LiveMapper mapper{s, kCamera, 0.001f, pool, handoff, rt::ThreadSpec{.name = "mapper_w1"}, stride};
};

TEST_F(LiveMapperInsertion, KeyframePointsGetFootprintSizedGaussians) {
  const int w = kW, h = kH;
  const PinholeCamera& camera = kCamera;

  // a wall 2 m ahead, sampled every `stride` pixels, with a flat kNN covariance
  const rt::FrameHandle fh = pool.acquire();
  ASSERT_TRUE(fh.valid());
  rt::Frame& f = pool.frame(fh);
  std::fill(f.depth.begin(), f.depth.end(), std::uint16_t{2000});
  std::fill(f.colour.begin(), f.colour.end(), std::uint8_t{128});
  KeyframeSlot* slot = handoff.acquire();
  ASSERT_NE(slot, nullptr);
  slot->keyframe = tracking::Keyframe{};
  for (int v = stride / 2; v < h; v += stride)
    for (int u = stride / 2; u < w; u += stride) add_wall_sample(slot->keyframe, u, v, 128);
  slot->frame = fh;
  handoff.publish(slot);
  mapper.tick();

  const mapping::GaussianMap& map = mapper.mapper().map();
  ASSERT_EQ(map.size(), slot->keyframe.cloud_c.size());
  const double angle = keyframe_sample_angle_rad(camera, stride);
  const double footprint_m = std::max(2.0 * angle, s.insert.voxel_m);
  for (std::size_t i = 0; i < map.size(); ++i) {
    double sd[3];
    for (int k = 0; k < 3; ++k) sd[k] = std::exp(double{map.log_scale[3 * i + k]});
    std::sort(sd, sd + 3);
    // in-plane: cover x footprint (an isotropic covariance: no stretch); GS-ICP SLAM's rule
    // would give sqrt(1e-3) / (2 * 2^1.5) = 5.6 mm here
    EXPECT_NEAR(sd[1], s.insert.cover * footprint_m, 1e-4) << "Gaussian " << i;
    EXPECT_NEAR(sd[2], s.insert.cover * footprint_m, 1e-4) << "Gaussian " << i;
  }
}

// Every Gaussian of the live map takes its patch's mean colour, as the replay's do
// (pipeline/mapper_keyframe.hpp): on stripes one pixel wide, the colour of the one pixel a
// sample falls on (what the live mapper once inserted) is 0 or 200, the patch mean in between.
TEST_F(LiveMapperInsertion, KeyframeGaussiansTakeTheirPatchMeanColour) {
  const int w = kW, h = kH;
  const rt::FrameHandle fh = pool.acquire();
  ASSERT_TRUE(fh.valid());
  rt::Frame& f = pool.frame(fh);
  std::fill(f.depth.begin(), f.depth.end(), std::uint16_t{2000});
  const auto stripe = [](int u) { return static_cast<std::uint8_t>(u % 2 == 0 ? 0 : 200); };
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      for (int c = 0; c < 3; ++c)
        f.colour[3 * (static_cast<std::size_t>(v) * w + static_cast<std::size_t>(u)) +
                 static_cast<std::size_t>(c)] = stripe(u);
  KeyframeSlot* slot = handoff.acquire();
  ASSERT_NE(slot, nullptr);
  slot->keyframe = tracking::Keyframe{};
  std::vector<int> us;
  for (int v = stride / 2; v < h - stride / 2; v += stride)
    for (int u = stride / 2; u < w - stride / 2; u += stride) {
      add_wall_sample(slot->keyframe, u, v, stripe(u));  // the one pixel's colour
      us.push_back(u);
    }
  slot->frame = fh;
  handoff.publish(slot);
  mapper.tick();

  const mapping::GaussianMap& map = mapper.mapper().map();
  ASSERT_EQ(map.size(), us.size());
  for (std::size_t i = 0; i < map.size(); ++i) {
    // the patch: columns u - 2 .. u + 2 (stride / 2 either side), every row alike
    double sum = 0.0;
    for (int u = us[i] - stride / 2; u <= us[i] + stride / 2; ++u) sum += stripe(u);
    const double patch_mean = sum / (stride + 1) / 255.0;
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(map.color_rgb[3 * i + static_cast<std::size_t>(k)], patch_mean, 1e-5)
          << "Gaussian " << i;
  }
}

}  // namespace
}  // namespace vigs::pipeline
