// The RgbdView of a FramePool slot reads the slot's own pixels (no copy) and gives the same
// points as the owned raw-depth image of the same frame.
#include "pipeline/pool_frame_view.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>

#include "tracking/depth_to_points.hpp"

namespace vigs::pipeline {
namespace {

TEST(PoolFrameView, ViewsTheSlotInPlace) {
  rt::FramePoolSettings ps;
  ps.slots = 2;
  ps.width = 32;
  ps.height = 24;
  ps.colour_channels = 3;
  rt::FramePool pool(ps);
  const rt::FrameHandle h = pool.acquire();
  ASSERT_TRUE(h.valid());
  rt::Frame& slot = pool.frame(h);
  slot.t_ns = 1'700'000'000'123'456'789;  // epoch-sized: seconds in a double would round it
  ImageU16 raw(32, 24, 1);
  ImageU8 rgb(32, 24, 3);
  for (int v = 0; v < 24; ++v)
    for (int u = 0; u < 32; ++u) {
      raw.at(u, v) = static_cast<std::uint16_t>(u == 3 ? 0 : 800 + 10 * u + 7 * v);
      for (int c = 0; c < 3; ++c) rgb.at(u, v, c) = static_cast<std::uint8_t>(u + 40 * c + v);
    }
  std::copy(raw.data.begin(), raw.data.end(), slot.depth.begin());
  std::copy(rgb.data.begin(), rgb.data.end(), slot.colour.begin());

  const RgbdView view = pool_frame_view(slot, pool.settings(), 1e-3f);
  EXPECT_EQ(view.t_ns, 1'700'000'000'123'456'789);
  EXPECT_EQ(view.depth_u16, slot.depth.data());
  EXPECT_EQ(view.colour, slot.colour.data());
  EXPECT_EQ(view.rgb_at(5, 7), (std::array<std::uint8_t, 3>{12, 52, 92}));

  const PinholeCamera cam{32, 24, 30.0, 30.0, 15.5, 11.5};
  tracking::DepthToPoints::Setting s;
  s.pixel_stride = 1;
  tracking::DepthToPoints d2p(cam, s);
  tracking::GaussianCloud from_view, from_image;
  const tracking::DepthToPointsStats a = d2p.convert(view, from_view);
  const tracking::DepthToPointsStats b = d2p.convert(raw, 0.001, rgb, from_image);
  EXPECT_EQ(a.invalid, 24);  // column 3
  EXPECT_EQ(a.points, b.points);
  EXPECT_TRUE(from_view.points_m == from_image.points_m);
  EXPECT_TRUE(from_view.colors_rgb == from_image.colors_rgb);
  pool.release(h);
}

TEST(PoolFrameView, MonoSlotReadsGrey) {
  rt::FramePoolSettings ps;
  ps.slots = 1;
  ps.width = 4;
  ps.height = 2;
  ps.colour_channels = 1;
  rt::FramePool pool(ps);
  const rt::FrameHandle h = pool.acquire();
  rt::Frame& slot = pool.frame(h);
  slot.colour[6] = 99;  // (2, 1)
  const RgbdView view = pool_frame_view(slot, pool.settings(), 1e-3f);
  EXPECT_EQ(view.colour_encoding, ColourEncoding::mono8);
  EXPECT_EQ(view.rgb_at(2, 1), (std::array<std::uint8_t, 3>{99, 99, 99}));
  pool.release(h);
}

}  // namespace
}  // namespace vigs::pipeline
