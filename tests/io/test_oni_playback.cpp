// ONI clip writer against the real OpenNI2 player (Debian libopenni2-0, OniFile driver): a
// 5-frame RGB-D clip with known patterns is opened with Device::open(path), played with
// setSpeed(-1) (one record per readFrame) and every frame and pixel must come back.
#include <OpenNI.h>
#include <gtest/gtest.h>

#include <cstring>

#include "io/io_error.hpp"
#include "io/oni/oni_clip_writer.hpp"
#include "mcap_test_util.hpp"

namespace vigs::io {
namespace {

constexpr std::uint32_t kW = 64, kH = 48;
constexpr int kFrames = 5;

std::uint16_t depth_at(int f, std::uint32_t x, std::uint32_t y) {
  return static_cast<std::uint16_t>(500 + 1000 * f + 37 * y + x);  // mm
}
std::uint8_t rgb_at(int f, std::uint32_t x, std::uint32_t y, int c) {
  return static_cast<std::uint8_t>(c == 0 ? 4 * x + f : c == 1 ? 5 * y + 3 * f : x ^ y ^ (17 * f));
}

// A bad clip makes OpenNI2 deliver nothing; wait with a timeout instead of blocking forever.
bool wait_for(openni::VideoStream& stream) {
  openni::VideoStream* streams[] = {&stream};
  int ready = -1;
  return openni::OpenNI::waitForAnyStream(streams, 1, &ready, 5000) == openni::STATUS_OK;
}

class OniPlayback : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    ASSERT_EQ(openni::OpenNI::initialize(), openni::STATUS_OK)
        << openni::OpenNI::getExtendedError();
  }
  static void TearDownTestSuite() { openni::OpenNI::shutdown(); }
};

TEST_F(OniPlayback, EveryFrameAndPixelComesBackThroughOpenNI2) {
  const std::string path = test::temp_path("clip.oni");
  {
    oni::OniClipWriter writer(path, {kW, kH, 30});
    for (int f = 0; f < kFrames; ++f) {
      std::vector<std::uint16_t> depth(kW * kH);
      std::vector<std::uint8_t> rgb(kW * kH * 3);
      for (std::uint32_t y = 0; y < kH; ++y) {
        for (std::uint32_t x = 0; x < kW; ++x) {
          depth[y * kW + x] = depth_at(f, x, y);
          for (int c = 0; c < 3; ++c) rgb[(y * kW + x) * 3 + c] = rgb_at(f, x, y, c);
        }
      }
      writer.add_frame(depth, rgb);
    }
    writer.close();
  }

  openni::Device device;
  ASSERT_EQ(device.open(path.c_str()), openni::STATUS_OK) << openni::OpenNI::getExtendedError();
  ASSERT_TRUE(device.isFile());
  openni::PlaybackControl* playback = device.getPlaybackControl();
  ASSERT_NE(playback, nullptr);
  ASSERT_EQ(playback->setSpeed(-1), openni::STATUS_OK);
  // Repeat stays on (the default). With repeat off, OpenNI2 2.2's player thread spins after the
  // End record while iterating its stream list unlocked, and stream destruction at close() then
  // crashes libOniFile now and then (seen 5 times in 40 runs here); with repeat on it parks
  // waiting for the next manual trigger. The wrap-around below also checks the End record.
  ASSERT_TRUE(playback->getRepeatEnabled());

  openni::VideoStream depth, color;
  ASSERT_EQ(depth.create(device, openni::SENSOR_DEPTH), openni::STATUS_OK)
      << openni::OpenNI::getExtendedError();
  ASSERT_EQ(color.create(device, openni::SENSOR_COLOR), openni::STATUS_OK)
      << openni::OpenNI::getExtendedError();
  EXPECT_EQ(playback->getNumberOfFrames(depth), kFrames);
  EXPECT_EQ(playback->getNumberOfFrames(color), kFrames);
  const openni::VideoMode dm = depth.getVideoMode();
  EXPECT_EQ(dm.getPixelFormat(), openni::PIXEL_FORMAT_DEPTH_1_MM);
  EXPECT_EQ(dm.getResolutionX(), static_cast<int>(kW));
  EXPECT_EQ(dm.getResolutionY(), static_cast<int>(kH));
  EXPECT_EQ(dm.getFps(), 30);
  EXPECT_EQ(color.getVideoMode().getPixelFormat(), openni::PIXEL_FORMAT_RGB888);
  EXPECT_NEAR(depth.getHorizontalFieldOfView(), 1.0226f, 1e-4f);
  ASSERT_EQ(depth.start(), openni::STATUS_OK);
  ASSERT_EQ(color.start(), openni::STATUS_OK);

  for (int f = 0; f < kFrames; ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    openni::VideoFrameRef d, c;
    ASSERT_TRUE(wait_for(depth)) << "no depth frame within 5 s";
    ASSERT_EQ(depth.readFrame(&d), openni::STATUS_OK);
    ASSERT_TRUE(wait_for(color)) << "no colour frame within 5 s";
    ASSERT_EQ(color.readFrame(&c), openni::STATUS_OK);
    EXPECT_EQ(d.getFrameIndex(), f + 1);
    EXPECT_EQ(c.getFrameIndex(), f + 1);
    ASSERT_EQ(d.getWidth(), static_cast<int>(kW));
    ASSERT_EQ(d.getHeight(), static_cast<int>(kH));
    ASSERT_EQ(d.getDataSize(), static_cast<int>(kW * kH * 2));
    ASSERT_EQ(c.getDataSize(), static_cast<int>(kW * kH * 3));
    const auto* dp = static_cast<const std::uint16_t*>(d.getData());
    const auto* cp = static_cast<const std::uint8_t*>(c.getData());
    int bad = 0;
    for (std::uint32_t y = 0; y < kH; ++y) {
      for (std::uint32_t x = 0; x < kW; ++x) {
        bad += dp[y * kW + x] != depth_at(f, x, y);
        for (int k = 0; k < 3; ++k) bad += cp[(y * kW + x) * 3 + k] != rgb_at(f, x, y, k);
      }
    }
    EXPECT_EQ(bad, 0);
  }
  // After the End record the clip starts over at frame 1.
  openni::VideoFrameRef again;
  ASSERT_TRUE(wait_for(depth));
  ASSERT_EQ(depth.readFrame(&again), openni::STATUS_OK);
  EXPECT_EQ(again.getFrameIndex(), 1);
  EXPECT_EQ(static_cast<const std::uint16_t*>(again.getData())[kW + 1], depth_at(0, 1, 1));

  depth.stop();
  color.stop();
  depth.destroy();
  color.destroy();
  device.close();
}

TEST(OniClipWriter, RejectsBadFramesAndSettings) {
  EXPECT_THROW(oni::OniClipWriter(test::temp_path("bad.oni"), {0, 10, 30}), IoError);
  oni::OniClipWriter w(test::temp_path("bad.oni"), {4, 4, 30});
  std::vector<std::uint16_t> depth(16);
  std::vector<std::uint8_t> rgb(47);
  EXPECT_THROW(w.add_frame(depth, rgb), IoError);
  EXPECT_THROW(w.close(), IoError);  // no frames
}

}  // namespace
}  // namespace vigs::io
