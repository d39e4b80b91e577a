// moving_pixels.hpp: the pixels of a keyframe's points flagged moving, and only those (with the
// stride block and the dilation around each), become -1 in its depth image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "pipeline/moving_pixels.hpp"
#include "tracking/depth_to_points.hpp"

namespace vigs::pipeline {
namespace {

constexpr int kW = 60, kH = 40;
// a person: pixels [20, 30) x [10, 30) at 1.5 m, before a wall at 3 m
bool in_person(int u, int v) {
  return u >= 20 && u < 30 && v >= 10 && v < 30;
}

struct Scene {
  PinholeCamera camera{kW, kH, 40.0, 40.0, 29.5, 19.5};
  ImageF32 depth{kW, kH, 1};
  tracking::Keyframe kf;
};

Scene make_scene(int stride) {
  Scene s;
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u)
      s.depth.data[static_cast<std::size_t>(v) * kW + u] = in_person(u, v) ? 1.5f : 3.0f;
  config::DepthToPointsSetting ds;
  ds.pixel_stride = stride;
  tracking::DepthToPoints d2p(s.camera, ds);
  d2p.convert(s.depth, ImageU8{}, s.kf.cloud_c);
  s.kf.moving.assign(s.kf.cloud_c.size(), 0);
  for (std::size_t i = 0; i < s.kf.cloud_c.size(); ++i)
    s.kf.moving[i] = s.kf.cloud_c.points_m[i].z() < 2.0f ? 1 : 0;  // the tracker's verdict
  return s;
}

TEST(MovingPixels, MarksThePersonAndItsRimOnly) {
  for (const int stride : {1, 2, 4}) {
    for (const int dilation : {0, 2}) {
      Scene s = make_scene(stride);
      const ImageF32 before = s.depth;
      const std::size_t marked = mask_moving_pixels(s.kf, s.camera, stride, dilation, s.depth);
      const int half = stride / 2 + dilation;
      std::size_t count = 0;
      for (int v = 0; v < kH; ++v) {
        for (int u = 0; u < kW; ++u) {
          const float d = s.depth.data[static_cast<std::size_t>(v) * kW + u];
          count += d < 0.0f ? 1 : 0;
          if (in_person(u, v)) {
            EXPECT_EQ(d, -1.0f) << u << "," << v << " stride " << stride;
            continue;
          }
          // distance (pixels, Chebyshev) to the person's box
          const int du = std::max({20 - u, u - 29, 0}), dv = std::max({10 - v, v - 29, 0});
          if (std::max(du, dv) > half) {
            EXPECT_EQ(d, before.data[static_cast<std::size_t>(v) * kW + u]) << u << "," << v;
          }
          if (std::max(du, dv) <= dilation) {
            EXPECT_EQ(d, -1.0f) << "the rim " << u << "," << v << " stride " << stride;
          }
        }
      }
      EXPECT_EQ(marked, count);
    }
  }
}

TEST(MovingPixels, NothingWithoutFlags) {
  Scene s = make_scene(2);
  const ImageF32 before = s.depth;
  std::fill(s.kf.moving.begin(), s.kf.moving.end(), 0);
  EXPECT_EQ(mask_moving_pixels(s.kf, s.camera, 2, 2, s.depth), 0u);
  s.kf.moving.clear();  // the test off: no flags at all
  EXPECT_EQ(mask_moving_pixels(s.kf, s.camera, 2, 2, s.depth), 0u);
  EXPECT_EQ(s.depth.data, before.data);
}

}  // namespace
}  // namespace vigs::pipeline
