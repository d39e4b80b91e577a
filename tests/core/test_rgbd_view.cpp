// RgbdView: raw depth to metres in single precision, strided rows, mono8 as grey, absent
// planes, the owned-image adapters and their checks, and the sanitising copies.
#include "core/types/rgbd_view.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace vigs {
namespace {

float depth_at(const RgbdView& f, int u, int v) {
  return f.with_depth_m([&](auto at) { return at(u, v); });
}

TEST(RgbdView, RawDepthIsFloatRawTimesScale) {
  ImageU16 raw(5, 3, 1);
  for (std::size_t i = 0; i < raw.data.size(); ++i)
    raw.data[i] = static_cast<std::uint16_t>(997 * i + 1);
  const RgbdView f = rgbd_view(42, raw, 1e-3f, ImageU8{});
  EXPECT_EQ(f.t_ns, 42);
  EXPECT_EQ(f.width_px, 5);
  EXPECT_EQ(f.height_px, 3);
  ASSERT_EQ(f.depth_encoding, DepthEncoding::u16_scaled);
  for (int v = 0; v < 3; ++v)
    for (int u = 0; u < 5; ++u) {
      // Bit-equal to what a reader converting 16UC1 into a float image stores.
      const float expect = static_cast<float>(raw.at(u, v)) * 1e-3f;
      EXPECT_EQ(depth_at(f, u, v), expect) << u << "," << v;
    }
  EXPECT_FALSE(f.has_colour());
  EXPECT_EQ(f.rgb_at(2, 1), (std::array<std::uint8_t, 3>{0, 0, 0}));
}

TEST(RgbdView, StridedRowsAndMonoColour) {
  // A 3x2 frame inside rows of 4 depth values and 5 colour bytes (padding set to junk).
  const std::vector<std::uint16_t> depth = {10, 11, 12, 999, 20, 21, 22, 999};
  const std::vector<std::uint8_t> grey = {1, 2, 3, 77, 77, 4, 5, 6, 77, 77};
  RgbdView f;
  f.width_px = 3;
  f.height_px = 2;
  f.depth_encoding = DepthEncoding::u16_scaled;
  f.depth_u16 = depth.data();
  f.depth_row_stride = 4;
  f.depth_scale_m = 0.5f;
  f.colour_encoding = ColourEncoding::mono8;
  f.colour = grey.data();
  f.colour_row_stride = 5;
  EXPECT_EQ(depth_at(f, 0, 1), 10.0f);
  EXPECT_EQ(depth_at(f, 2, 0), 6.0f);
  EXPECT_EQ(f.rgb_at(1, 1), (std::array<std::uint8_t, 3>{5, 5, 5}));
  ImageU8 rgb;
  copy_rgb8(f, rgb);
  ASSERT_EQ(rgb.channels, 3);
  ASSERT_EQ(rgb.data.size(), 18u);
  EXPECT_EQ(rgb.at(2, 1, 0), 6);
  EXPECT_EQ(rgb.at(2, 1, 2), 6);
  EXPECT_EQ(rgb.at(0, 0, 1), 1);
}

TEST(RgbdView, FloatDepthAndSanitisingCopy) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  ImageF32 d(4, 1, 1);
  d.data = {1.25f, nan, -2.0f, inf};
  ImageU8 rgb(4, 1, 3);
  rgb.at(3, 0, 0) = 9;
  rgb.at(3, 0, 2) = 200;
  const RgbdView f = rgbd_view(7, d, rgb);
  EXPECT_EQ(depth_at(f, 0, 0), 1.25f);
  EXPECT_TRUE(std::isnan(depth_at(f, 1, 0)));  // the view does not hide bad values...
  EXPECT_EQ(f.rgb_at(3, 0), (std::array<std::uint8_t, 3>{9, 0, 200}));
  ImageF32 out;
  copy_depth_m(f, out);  // ...its copy does
  EXPECT_EQ(out.data, (std::vector<float>{1.25f, 0.0f, 0.0f, 0.0f}));
}

TEST(RgbdView, NoDepthReadsAsNoMeasurement) {
  const ImageU8 rgb(6, 4, 3, 100);
  const RgbdView f = rgbd_view(0, ImageF32{}, rgb);
  EXPECT_FALSE(f.has_depth());
  EXPECT_EQ(f.width_px, 6);
  EXPECT_EQ(depth_at(f, 5, 3), 0.0f);
  ImageF32 out(1, 1, 1, 5.0f);
  copy_depth_m(f, out);
  EXPECT_EQ(out.data, std::vector<float>(24, 0.0f));
}

TEST(RgbdView, OwnedImagesMustAgree) {
  EXPECT_THROW(rgbd_view(0, ImageF32(8, 4, 1), ImageU8(4, 4, 3)), std::invalid_argument);
  EXPECT_THROW(rgbd_view(0, ImageF32(8, 4, 1), ImageU8(8, 4, 2)), std::invalid_argument);
  EXPECT_THROW(rgbd_view(0, ImageF32(8, 4, 2), ImageU8{}), std::invalid_argument);
  EXPECT_THROW(rgbd_view(0, ImageU16(8, 4, 1), 1e-3f, ImageU8(8, 5, 3)), std::invalid_argument);
  EXPECT_NO_THROW(rgbd_view(0, ImageU16(8, 4, 1), 1e-3f, ImageU8(8, 4, 1)));
}

}  // namespace
}  // namespace vigs
