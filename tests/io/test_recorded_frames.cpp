// The recording's frame reader: integer stamps kept exactly, depth paired with colour within the
// stated tolerance, 16UC1 and 32FC1 depth, rgb8/mono8 viewed in place and bgr8 converted, and
// the simulator's person mask when asked for.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "io/mcap/mcap_writer.hpp"
#include "io/recording/recorded_frames.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/typed_io.hpp"
#include "mcap_test_util.hpp"

namespace vigs::io {
namespace {

constexpr int kW = 4, kH = 3;
constexpr std::int64_t kT0 = 1'700'000'000'123'456'789;  // seconds in a double would round it

struct Writer {
  explicit Writer(const std::string& path) : w(path, {}) {
    info = ros_msgs::add_channel<ros_msgs::CameraInfo>(w, topics::kCameraInfo.name);
    rgb = ros_msgs::add_channel<ros_msgs::Image>(w, topics::kRgb.name);
    depth = ros_msgs::add_channel<ros_msgs::Image>(w, topics::kDepth.name);
  }
  void frame(std::int64_t t_ns, const std::string& colour_encoding, std::int64_t depth_t_ns,
             const std::string& depth_encoding) {
    ros_msgs::CameraInfo ci;
    ci.header.stamp = ros_msgs::Time::from_ns(t_ns);
    ci.width = kW;
    ci.height = kH;
    ci.k = {10, 0, 1.5, 0, 10, 1, 0, 0, 1};
    const auto t = static_cast<std::uint64_t>(t_ns);
    ros_msgs::write_message(w, info, t, ci, scratch);
    ros_msgs::Image c;
    c.header = ci.header;
    c.width = kW;
    c.height = kH;
    c.encoding = colour_encoding;
    const std::uint32_t ch = colour_encoding == "mono8" ? 1 : 3;
    c.step = kW * ch + 2;  // padded rows
    c.data.assign(static_cast<std::size_t>(c.step) * kH, 0xEE);
    for (std::uint32_t y = 0; y < kH; ++y)
      for (std::uint32_t i = 0; i < kW * ch; ++i) c.data[y * c.step + i] = (10 * y + i) & 0xFF;
    ros_msgs::write_message(w, rgb, t, c, scratch);
    ros_msgs::Image d;
    d.header.stamp = ros_msgs::Time::from_ns(depth_t_ns);
    d.width = kW;
    d.height = kH;
    d.encoding = depth_encoding;
    const std::uint32_t bytes = depth_encoding == "16UC1" ? 2 : 4;
    d.step = kW * bytes;
    d.data.resize(static_cast<std::size_t>(d.step) * kH);
    for (std::uint32_t p = 0; p < kW * kH; ++p) {
      if (bytes == 2) {
        const auto mm = static_cast<std::uint16_t>(1000 + p);
        d.data[2 * p] = mm & 0xFF;
        d.data[2 * p + 1] = static_cast<std::uint8_t>(mm >> 8);
      } else {
        const float m = 1.0f + 0.25f * static_cast<float>(p);
        std::memcpy(d.data.data() + 4 * p, &m, 4);
      }
    }
    ros_msgs::write_message(w, depth, static_cast<std::uint64_t>(depth_t_ns), d, scratch);
  }
  /// A person mask (mono8 unless `encoding` says otherwise, rows padded): pixel p holds
  /// p % 2 ? 255 : 0.
  void mask(std::int64_t t_ns, std::uint32_t width = kW, const std::string& encoding = "mono8") {
    if (mask_ch == 0)
      mask_ch = ros_msgs::add_channel<ros_msgs::Image>(w, topics::kDynamicMask.name);
    ros_msgs::Image m;
    m.header.stamp = ros_msgs::Time::from_ns(t_ns);
    m.width = width;
    m.height = kH;
    m.encoding = encoding;
    m.step = width + 3;
    m.data.assign(static_cast<std::size_t>(m.step) * kH, 0x77);
    for (std::uint32_t y = 0; y < kH; ++y)
      for (std::uint32_t x = 0; x < width; ++x)
        m.data[y * m.step + x] = (y * width + x) % 2 ? 255 : 0;
    ros_msgs::write_message(w, mask_ch, static_cast<std::uint64_t>(t_ns), m, scratch);
  }
  mcap::McapWriter w;
  std::uint16_t info = 0, rgb = 0, depth = 0, mask_ch = 0;
  std::vector<std::uint8_t> scratch;
};

struct Seen {
  std::int64_t t_ns;
  DepthEncoding depth;
  float depth_m_at_2_1;
  std::array<std::uint8_t, 3> rgb_at_1_2;
};

std::vector<Seen> read_all(const std::string& path) {
  std::vector<Seen> seen;
  io::for_each_recorded_frame(path, [&](const io::RecordedFrame& f) {
    EXPECT_EQ(f.view.width_px, kW);
    EXPECT_EQ(f.camera.fx_px, 10.0);
    const float z = f.view.with_depth_m([](auto at) { return at(2, 1); });
    seen.push_back({f.view.t_ns, f.view.depth_encoding, z, f.view.rgb_at(1, 2)});
  });
  return seen;
}

TEST(RecordedFrames, StampsStayIntegerAndDepthPairsWithinTolerance) {
  const std::string path = test::temp_path("frames_pairing.mcap");
  {
    Writer w(path);
    const std::int64_t half = kDepthPairToleranceNs / 2;
    w.frame(kT0, "rgb8", kT0, "16UC1");                                   // same stamp
    w.frame(kT0 + 50'000'000, "rgb8", kT0 + 50'000'000 + half, "32FC1");  // inside
    w.frame(kT0 + 100'000'000, "rgb8", kT0 + 100'000'000 - 2 * kDepthPairToleranceNs,
            "16UC1");  // outside: the frame has no depth
    w.w.close();
  }
  const std::vector<Seen> seen = read_all(path);
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen[0].t_ns, kT0);
  EXPECT_EQ(seen[1].t_ns, kT0 + 50'000'000);
  EXPECT_EQ(seen[0].depth, DepthEncoding::u16_scaled);
  EXPECT_EQ(seen[0].depth_m_at_2_1, static_cast<float>(1000 + 6) * 1e-3f);  // pixel 6, mm
  EXPECT_EQ(seen[1].depth, DepthEncoding::f32_metres);
  EXPECT_EQ(seen[1].depth_m_at_2_1, 2.5f);
  EXPECT_EQ(seen[2].depth, DepthEncoding::none);
  EXPECT_EQ(seen[2].depth_m_at_2_1, 0.0f);
  // rgb8 at (1, 2): row 2 starts at value 20, pixel 1 at byte 3.
  EXPECT_EQ(seen[0].rgb_at_1_2, (std::array<std::uint8_t, 3>{23, 24, 25}));
}

TEST(RecordedFrames, MonoAndBgrColour) {
  const std::string path = test::temp_path("frames_colour.mcap");
  {
    Writer w(path);
    w.frame(kT0, "mono8", kT0, "16UC1");
    w.frame(kT0 + 50'000'000, "bgr8", kT0 + 50'000'000, "16UC1");
    w.w.close();
  }
  const std::vector<Seen> seen = read_all(path);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_EQ(seen[0].rgb_at_1_2, (std::array<std::uint8_t, 3>{21, 21, 21}));
  EXPECT_EQ(seen[1].rgb_at_1_2, (std::array<std::uint8_t, 3>{25, 24, 23}));
}

/// What a frame carried when read with the mask topic.
struct SeenMask {
  std::int64_t t_ns;
  bool has_depth;
  std::vector<std::uint8_t> mask;  ///< empty: none
};

std::vector<SeenMask> read_with_masks(const std::string& path) {
  std::vector<SeenMask> seen;
  io::for_each_recorded_frame(
      path,
      [&](const io::RecordedFrame& f) {
        SeenMask s{f.view.t_ns, f.view.has_depth(), {}};
        if (f.dynamic_mask != nullptr) s.mask.assign(f.dynamic_mask, f.dynamic_mask + kW * kH);
        seen.push_back(std::move(s));
      },
      std::string(topics::kRgb.name), std::string(topics::kCameraInfo.name),
      std::string(topics::kDepth.name), kDepthPairToleranceNs,
      std::string(topics::kDynamicMask.name));
  return seen;
}

TEST(RecordedFrames, PersonMaskOfTheFramesStampWhenAskedFor) {
  const std::string path = test::temp_path("frames_mask.mcap");
  {
    Writer w(path);
    w.frame(kT0, "rgb8", kT0, "16UC1");
    w.mask(kT0);  // after the depth, as the simulator writes it
    w.frame(kT0 + 50'000'000, "rgb8", kT0 + 50'000'000, "16UC1");
    w.mask(kT0 + 50'000'001);                                        // another stamp: ignored
    w.frame(kT0 + 100'000'000, "rgb8", kT0 + 100'000'000, "16UC1");  // none
    w.mask(kT0 + 150'000'000);  // before its frame's colour image
    w.frame(kT0 + 150'000'000, "rgb8", kT0 + 150'000'000, "16UC1");
    w.w.close();
  }
  std::vector<std::uint8_t> expected(kW * kH);
  for (std::size_t p = 0; p < expected.size(); ++p) expected[p] = p % 2 ? 255 : 0;
  const std::vector<SeenMask> seen = read_with_masks(path);
  ASSERT_EQ(seen.size(), 4u);
  EXPECT_EQ(seen[0].mask, expected);  // padding dropped
  EXPECT_TRUE(seen[1].mask.empty());
  EXPECT_TRUE(seen[2].mask.empty());
  // A mask before its colour image belongs to no frame (the reader pairs what follows).
  EXPECT_TRUE(seen[3].mask.empty());
  for (const SeenMask& s : seen) EXPECT_TRUE(s.has_depth) << s.t_ns;

  // Without the mask topic: the frames as before, none with a mask.
  std::size_t plain = 0;
  io::for_each_recorded_frame(path, [&](const io::RecordedFrame& f) {
    EXPECT_EQ(f.dynamic_mask, nullptr);
    EXPECT_EQ(f.view.t_ns, seen[plain].t_ns);
    EXPECT_TRUE(f.view.has_depth());
    ++plain;
  });
  EXPECT_EQ(plain, 4u);
}

TEST(RecordedFrames, PersonMaskOfAnotherSizeOrEncodingIsAnErrorNamingItsOffset) {
  for (const bool wrong_size : {true, false}) {
    const std::string path = test::temp_path("frames_bad_mask.mcap");
    {
      Writer w(path);
      w.frame(kT0, "rgb8", kT0, "16UC1");
      w.mask(kT0);
      w.frame(kT0 + 50'000'000, "rgb8", kT0 + 50'000'000, "16UC1");
      w.mask(kT0 + 50'000'000, wrong_size ? kW - 1 : kW, wrong_size ? "mono8" : "mono16");
      w.w.close();
    }
    try {
      read_with_masks(path);
      ADD_FAILURE() << "no error, wrong size " << wrong_size;
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(path + ": /vigs/ground_truth/dynamic_mask message at byte "),
                std::string::npos)
          << what;
      EXPECT_NE(what.find(wrong_size ? "mask is 3x3 'mono8' but its frame is 4x3"
                                     : "mask is 4x3 'mono16' but its frame is 4x3"),
                std::string::npos)
          << what;
    }
    // Not asked for, the mask is not read.
    EXPECT_EQ(read_all(path).size(), 2u);
  }
}

}  // namespace
}  // namespace vigs::io
