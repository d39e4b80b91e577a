// The V4L2 RGB-D driver's whole streaming state machine against FakeV4l2Device, a fake with the
// kernel's semantics behind the driver's open/ioctl/mmap/poll seam (this kernel has no video
// devices): a normal stream paired by kernel timestamp with exact pixels, padded rows, EAGAIN
// wake-ups, corrupt buffers, sequence gaps, unpaired frames, a full ring and an empty pool,
// buffers without a monotonic stamp, ENODEV mid-stream and the reopen after a re-plug, start-up
// errors naming the node.
#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <chrono>
#include <cstring>
#include <functional>
#include <thread>
#include <vector>

#include "drivers/v4l2/v4l2_rgbd_driver.hpp"
#include "fake_v4l2_device.hpp"
#include "rt/clock.hpp"

namespace vigs::drivers {
namespace {

using testing::FakeFrame;
using testing::FakeNodeSpec;
using testing::FakeV4l2Device;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr std::uint32_t kW = 32, kH = 24;
constexpr std::uint32_t kDepthStride = kW * 2 + 16;  // padded rows: copied row by row
const std::string kDepthNode = "/dev/v4l/by-id/fake-depth";
const std::string kColourNode = "/dev/v4l/by-id/fake-colour";
constexpr std::int64_t kPeriodNs = 33'333'333;  // 30 Hz
constexpr std::int64_t kT0 = 5'000'000'000;

std::uint16_t depth_at(int f, std::uint32_t x, std::uint32_t y) {
  return static_cast<std::uint16_t>(500 + 700 * f + 31 * y + x);
}
std::uint8_t grey_at(int f, std::uint32_t x, std::uint32_t y) {
  return static_cast<std::uint8_t>(3 * x + 5 * y + 17 * f);
}

std::vector<std::uint8_t> depth_bytes(int f) {
  std::vector<std::uint8_t> b(std::size_t{kDepthStride} * kH, 0xEE);  // padding: garbage
  for (std::uint32_t y = 0; y < kH; ++y) {
    for (std::uint32_t x = 0; x < kW; ++x) {
      const std::uint16_t d = depth_at(f, x, y);
      std::memcpy(&b[y * kDepthStride + 2 * x], &d, 2);
    }
  }
  return b;
}
std::vector<std::uint8_t> grey_bytes(int f) {
  std::vector<std::uint8_t> b(std::size_t{kW} * kH);
  for (std::uint32_t y = 0; y < kH; ++y) {
    for (std::uint32_t x = 0; x < kW; ++x) b[y * kW + x] = grey_at(f, x, y);
  }
  return b;
}

bool wait_until(const std::function<bool()>& done, std::chrono::milliseconds limit = 5000ms) {
  const auto deadline = Clock::now() + limit;
  while (!done()) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(1ms);
  }
  return true;
}

class V4l2Driver : public ::testing::Test {
 protected:
  void SetUp() override {
    fake.add_node(kDepthNode, {.pixelformat = V4L2_PIX_FMT_Z16,
                               .width = kW,
                               .height = kH,
                               .bytes_per_line = kDepthStride,
                               .size_image = kDepthStride * kH});
    fake.add_node(kColourNode, {.pixelformat = V4L2_PIX_FMT_GREY,
                                .width = kW,
                                .height = kH,
                                .bytes_per_line = kW,
                                .size_image = kW * kH});
  }
  V4l2RgbdDriverSettings settings() const {
    V4l2RgbdDriverSettings s;
    s.depth_device = kDepthNode;
    s.colour_device = kColourNode;
    s.colour_format = V4l2PixelFormat::kGrey;
    s.width_px = kW;
    s.height_px = kH;
    s.rate_hz = 30.0;
    s.realtime_thread = false;
    s.pin_cpu = false;
    s.frame_timeout_ms = 1000;
    return s;
  }
  // One camera instant: depth and colour with stamps `offset_ns` apart. Waits until the driver
  // has taken both buffers back (so the next push finds a queued buffer).
  void push_pair(int f, std::int64_t offset_ns = 0, std::uint32_t skip = 0) {
    const auto d = depth_bytes(f);
    const auto c = grey_bytes(f);
    const std::int64_t t = kT0 + f * kPeriodNs;
    ASSERT_TRUE(fake.push_frame(kDepthNode, {.bytes = d, .t_ns = t, .skip_sequence = skip}));
    ASSERT_TRUE(fake.push_frame(kColourNode, {.bytes = c, .t_ns = t + offset_ns}));
  }
  void wait_requeued(std::size_t buffers = 4) {
    ASSERT_TRUE(wait_until(
        [&] { return fake.queued(kDepthNode) >= buffers && fake.queued(kColourNode) >= buffers; }));
  }
  // Pops everything queued; checks pixels against depth pattern f = depth[0] decoded.
  struct Got {
    std::vector<std::int64_t> t_ns;
    std::vector<std::uint64_t> sequence;
    std::vector<int> clip_frame;
    int bad = 0;
    bool end_marker = false;
  };
  static Got drain(rt::SpscRing<rt::FrameHandle>& from, rt::FramePool& slots) {
    Got g;
    rt::FrameHandle h;
    while (from.try_pop(h)) {
      if (!h.valid()) {
        g.end_marker = true;
        continue;
      }
      const rt::Frame& fr = slots.frame(h);
      const int f = (fr.depth[0] - 500) / 700;
      g.clip_frame.push_back(f);
      g.t_ns.push_back(fr.t_ns);
      g.sequence.push_back(fr.sequence);
      for (std::uint32_t y = 0; y < kH; ++y) {
        for (std::uint32_t x = 0; x < kW; ++x) {
          g.bad += fr.depth[y * kW + x] != depth_at(f, x, y);
          g.bad += fr.colour[y * kW + x] != grey_at(f, x, y);
        }
      }
      slots.release(h);
    }
    return g;
  }

  FakeV4l2Device fake;
  rt::FramePool pool{{.slots = 16, .width = kW, .height = kH, .colour_channels = 1}};
  rt::SpscRing<rt::FrameHandle> ring{16};
};

TEST_F(V4l2Driver, NormalStreamPairsByKernelTimestampWithExactPixels) {
  V4l2RgbdDriver driver(settings(), pool, ring, fake);
  driver.start();
  EXPECT_EQ(driver.state(), DeviceState::kStreaming);
  EXPECT_TRUE(fake.streaming(kDepthNode));
  EXPECT_EQ(fake.queued(kDepthNode), 4u);  // every mmap buffer queued before STREAMON
  constexpr int kFrames = 10;
  for (int f = 0; f < kFrames; ++f) {
    push_pair(f, f % 2 ? 2'000'000 : -3'000'000);  // a few ms apart: still one instant
    wait_requeued();
  }
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.delivered == kFrames; }));
  const Got g = drain(ring, pool);
  ASSERT_EQ(g.t_ns.size(), static_cast<std::size_t>(kFrames));
  for (int f = 0; f < kFrames; ++f) {
    EXPECT_EQ(g.clip_frame[f], f);
    EXPECT_EQ(g.sequence[f], static_cast<std::uint64_t>(f));
    const std::int64_t t = kT0 + f * kPeriodNs;
    EXPECT_EQ(g.t_ns[f], t - t % 1000) << "the depth buffer's kernel stamp (timeval: whole us)";
  }
  EXPECT_EQ(g.bad, 0);
  const V4l2RgbdCounters c = driver.counters();
  EXPECT_EQ(c.rgbd.depth_read, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(c.rgbd.colour_read, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(c.rgbd.frames_read, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(c.rgbd.unpaired, 0u);
  EXPECT_EQ(c.kernel_dropped, 0u);
  EXPECT_EQ(c.corrupt_buffers, 0u);
  EXPECT_EQ(c.host_stamped, 0u);
  EXPECT_EQ(c.rgbd.opens, 1u);
  driver.stop();
  EXPECT_FALSE(fake.streaming(kDepthNode));
  EXPECT_EQ(pool.available(), pool.capacity());
}

TEST_F(V4l2Driver, EagainCorruptBuffersAndSequenceGapsAreCountedAndSkipped) {
  V4l2RgbdDriver driver(settings(), pool, ring, fake);
  driver.start();
  push_pair(0);
  wait_requeued();
  fake.spurious_wakeups(kColourNode, 3);  // poll says ready, DQBUF says EAGAIN
  ASSERT_TRUE(wait_until([&] { return driver.counters().eagain >= 3; }));
  // A corrupt depth buffer (V4L2_BUF_FLAG_ERROR): requeued at once, its colour stays unpaired.
  const auto d1 = depth_bytes(1);
  const auto c1 = grey_bytes(1);
  ASSERT_TRUE(
      fake.push_frame(kDepthNode, {.bytes = d1, .t_ns = kT0 + kPeriodNs, .error_flag = true}));
  ASSERT_TRUE(fake.push_frame(kColourNode, {.bytes = c1, .t_ns = kT0 + kPeriodNs}));
  wait_requeued(3);
  // The kernel lost frames 2..4 of the depth node (no buffer was queued): the gap is counted.
  push_pair(5, 0, 3);
  wait_requeued();
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.delivered == 2; }));
  const V4l2RgbdCounters c = driver.counters();
  EXPECT_EQ(c.eagain, 3u);
  EXPECT_EQ(c.corrupt_buffers, 1u);
  EXPECT_EQ(c.kernel_dropped, 3u);
  EXPECT_EQ(c.rgbd.unpaired, 1u);  // colour 1 had no depth partner
  EXPECT_EQ(c.rgbd.read_errors, 0u);
  const Got g = drain(ring, pool);
  ASSERT_EQ(g.clip_frame.size(), 2u);
  EXPECT_EQ(g.clip_frame[0], 0);
  EXPECT_EQ(g.clip_frame[1], 5);
  EXPECT_EQ(g.bad, 0);
  EXPECT_EQ(driver.state(), DeviceState::kStreaming);
  driver.stop();
}

TEST_F(V4l2Driver, FramesBeyondTheTolerancePairWithNobodyAndAreCounted) {
  V4l2RgbdDriverSettings s = settings();
  s.pair_tolerance_us = 5000;  // stated: 5 ms
  V4l2RgbdDriver driver(s, pool, ring, fake);
  driver.start();
  push_pair(0, 4'900'000);  // 4.9 ms: pairs
  wait_requeued();
  push_pair(1, 6'000'000);  // 6 ms: the older (depth) is unpaired, colour waits
  wait_requeued(3);
  push_pair(2, 0);  // the waiting colour 1 is older than depth 2 by 27 ms: unpaired; 2 pairs
  wait_requeued();
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.delivered == 2; }));
  const V4l2RgbdCounters c = driver.counters();
  EXPECT_EQ(c.rgbd.unpaired, 2u);
  EXPECT_EQ(c.rgbd.depth_read + c.rgbd.colour_read, 2 * c.rgbd.frames_read + c.rgbd.unpaired);
  const Got g = drain(ring, pool);
  ASSERT_EQ(g.clip_frame.size(), 2u);
  EXPECT_EQ(g.clip_frame[0], 0);
  EXPECT_EQ(g.clip_frame[1], 2);
  driver.stop();
}

TEST_F(V4l2Driver, FullRingDropsNewestAndEmptyPoolIsCountedNeverBlocking) {
  rt::FramePool small_pool({.slots = 3, .width = kW, .height = kH, .colour_channels = 1});
  rt::SpscRing<rt::FrameHandle> small_ring(2);
  V4l2RgbdDriver driver(settings(), small_pool, small_ring, fake);
  driver.start();
  for (int f = 0; f < 6; ++f) {  // nobody reads
    push_pair(f);
    wait_requeued();
  }
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.frames_read == 6; }));
  V4l2RgbdCounters c = driver.counters();
  EXPECT_EQ(c.rgbd.delivered, 2u);
  EXPECT_EQ(c.rgbd.dropped_ring_full, 4u);
  EXPECT_EQ(c.rgbd.dropped_pool_empty, 0u);
  // The consumer now holds both queued frames and one more: the pool (3) runs dry.
  rt::FrameHandle a, b;
  ASSERT_TRUE(small_ring.try_pop(a));
  ASSERT_TRUE(small_ring.try_pop(b));
  rt::FrameHandle held = small_pool.acquire();
  ASSERT_TRUE(held.valid());
  push_pair(6);
  wait_requeued();
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.frames_read == 7; }));
  c = driver.counters();
  EXPECT_EQ(c.rgbd.dropped_pool_empty, 1u);
  EXPECT_EQ(c.rgbd.delivered + c.rgbd.dropped_ring_full + c.rgbd.dropped_pool_empty,
            c.rgbd.frames_read);
  small_pool.release(a);
  small_pool.release(b);
  small_pool.release(held);
  driver.stop();
  EXPECT_EQ(small_pool.available(), small_pool.capacity());
}

TEST_F(V4l2Driver, BuffersWithoutAMonotonicStampGetTheHostTimeAndAreCounted) {
  V4l2RgbdDriver driver(settings(), pool, ring, fake);
  driver.start();
  const auto d = depth_bytes(0);
  const auto c = grey_bytes(0);
  const std::int64_t before = rt::monotonic_ns();
  ASSERT_TRUE(fake.push_frame(kDepthNode, {.bytes = d, .t_ns = 77, .monotonic_flag = false}));
  ASSERT_TRUE(fake.push_frame(kColourNode, {.bytes = c, .t_ns = 77, .monotonic_flag = false}));
  wait_requeued();
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.frames_read >= 1; }));
  const std::int64_t after = rt::monotonic_ns();
  EXPECT_EQ(driver.counters().host_stamped, 2u);
  const Got g = drain(ring, pool);
  // Both host stamps lie within the push window, so they paired (half a period tolerance).
  ASSERT_EQ(g.t_ns.size(), 1u);
  EXPECT_GE(g.t_ns[0], before);
  EXPECT_LE(g.t_ns[0], after);
  driver.stop();
}

TEST_F(V4l2Driver, EnodevMidStreamLosesTheDeviceAndReopensItWhenItComesBack) {
  V4l2RgbdDriver driver(settings(), pool, ring, fake);
  driver.start();
  for (int f = 0; f < 3; ++f) {
    push_pair(f);
    wait_requeued();
  }
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.delivered == 3; }));
  fake.unplug(kDepthNode);  // ENODEV from now on, poll says POLLERR | POLLHUP, open ENOENT
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.device_gone == 1; }));
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.open_failures >= 2; }));
  EXPECT_EQ(driver.state(), DeviceState::kOpening);
  EXPECT_FALSE(driver.end_of_stream());
  EXPECT_FALSE(fake.streaming(kColourNode));  // both nodes closed: the pair is one device
  fake.replug(kDepthNode);
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.reopens == 1; }));
  wait_requeued();
  for (int f = 3; f < 6; ++f) {
    push_pair(f);
    wait_requeued();
  }
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.delivered == 6; }));
  const Got g = drain(ring, pool);
  ASSERT_EQ(g.clip_frame.size(), 6u);
  for (int f = 0; f < 6; ++f) EXPECT_EQ(g.clip_frame[f], f);
  for (std::size_t i = 1; i < g.t_ns.size(); ++i) EXPECT_GT(g.t_ns[i], g.t_ns[i - 1]);
  EXPECT_EQ(g.bad, 0);
  const V4l2RgbdCounters c = driver.counters();
  EXPECT_EQ(c.rgbd.losses, 1u);
  EXPECT_EQ(c.rgbd.opens, 2u);
  EXPECT_EQ(fake.opens(kDepthNode), 2);  // failed opens never reached the unplugged node
  driver.stop();
  EXPECT_EQ(pool.available(), pool.capacity());
}

TEST_F(V4l2Driver, WithoutReopenALostDeviceEndsTheStreamWithAMarker) {
  V4l2RgbdDriverSettings s = settings();
  s.reopen = false;
  V4l2RgbdDriver driver(s, pool, ring, fake);
  driver.start();
  push_pair(0);
  wait_requeued();
  fake.unplug(kColourNode);
  ASSERT_TRUE(wait_until([&] { return driver.end_of_stream(); }));
  EXPECT_EQ(driver.state(), DeviceState::kFailed);
  const Got g = drain(ring, pool);
  EXPECT_EQ(g.clip_frame.size(), 1u);
  EXPECT_TRUE(g.end_marker);
  driver.stop();
}

TEST_F(V4l2Driver, AStreamThatStopsSendingIsLostAfterTheFrameTimeout) {
  V4l2RgbdDriverSettings s = settings();
  s.frame_timeout_ms = 150;
  V4l2RgbdDriver driver(s, pool, ring, fake);
  driver.start();
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.frame_timeouts >= 1; }));
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.reopens >= 1; }));
  EXPECT_GE(driver.counters().rgbd.timeouts, 3u);
  driver.stop();
}

TEST_F(V4l2Driver, StartErrorsNameTheNodeAndBothSizes) {
  V4l2RgbdDriverSettings s = settings();
  s.colour_device = "/dev/v4l/by-id/not-there";
  {
    V4l2RgbdDriver driver(s, pool, ring, fake);
    try {
      driver.start();
      FAIL() << "start() opened a missing node";
    } catch (const V4l2Error& e) {
      EXPECT_NE(std::string(e.what()).find("not-there': open: No such file"), std::string::npos)
          << e.what();
    }
    EXPECT_FALSE(driver.running());
    EXPECT_FALSE(fake.streaming(kDepthNode));  // the depth node opened first is closed again
  }
  fake.add_node("/dev/small", {.pixelformat = V4L2_PIX_FMT_GREY,
                               .width = 16,
                               .height = 12,
                               .bytes_per_line = 16,
                               .size_image = 16 * 12});
  s = settings();
  s.colour_device = "/dev/small";
  V4l2RgbdDriver driver(s, pool, ring, fake);
  try {
    driver.start();
    FAIL() << "start() accepted a 16x12 node for a 32x24 camera";
  } catch (const V4l2Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("/dev/small"), std::string::npos) << msg;
    EXPECT_NE(msg.find("16x12 GREY"), std::string::npos) << msg;
    EXPECT_NE(msg.find("32x24 GREY"), std::string::npos) << msg;
  }
}

TEST_F(V4l2Driver, WaitForDeviceOpensOnceTheNodesAppear) {
  FakeV4l2Device late;
  V4l2RgbdDriverSettings s = settings();
  s.wait_for_device = true;
  late.add_node(kDepthNode, {.pixelformat = V4L2_PIX_FMT_Z16,
                             .width = kW,
                             .height = kH,
                             .bytes_per_line = kDepthStride,
                             .size_image = kDepthStride * kH});
  late.add_node(kColourNode, {.pixelformat = V4L2_PIX_FMT_GREY,
                              .width = kW,
                              .height = kH,
                              .bytes_per_line = kW,
                              .size_image = kW * kH});
  late.unplug(kDepthNode);
  V4l2RgbdDriver driver(s, pool, ring, late);
  driver.start();
  ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.open_failures >= 1; }));
  late.replug(kDepthNode);
  ASSERT_TRUE(wait_until([&] { return driver.state() == DeviceState::kStreaming; }));
  EXPECT_EQ(driver.counters().rgbd.opens, 1u);
  driver.stop();
}

}  // namespace
}  // namespace vigs::drivers
