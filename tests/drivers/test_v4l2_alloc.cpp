// The V4L2 driver's streaming loop does not allocate once frames flow: global operator new is
// replaced (counting_new.hpp) and calls on the thread named `rgbd_driver` after its first two
// pairs are counted while it streams a Z16 + YUYV pair (libv4lconvert) from the fake device,
// through corrupt buffers, a sequence gap, spurious wake-ups and a full ring. (libv4lconvert's
// own buffers come from malloc, which is not seen here; it keeps them between frames.)
#include <dlfcn.h>
#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>
#include <vector>

#include "../common/counting_new.hpp"
#include "drivers/v4l2/v4l2_rgbd_driver.hpp"
#include "fake_v4l2_device.hpp"

namespace {
std::atomic<const vigs::drivers::V4l2RgbdDriver*> g_driver{nullptr};
std::atomic<long> g_warmup{0};
std::atomic<long> g_loop{0};
void* g_callers[8] = {};
}  // namespace

void vigs::test::on_operator_new(std::size_t, void* caller) noexcept {
  if (!on_thread_named("rgbd_driver")) return;
  const vigs::drivers::V4l2RgbdDriver* d = g_driver.load();
  if (d != nullptr && d->counters().rgbd.frames_read >= 2) {
    const long n = g_loop.fetch_add(1);
    if (n < 8) g_callers[n] = caller;
  } else {
    g_warmup.fetch_add(1);
  }
}

namespace vigs::drivers {
namespace {

using namespace std::chrono_literals;

TEST(V4l2Driver, StreamingLoopDoesNotAllocateAfterTheFirstFrames) {
  constexpr std::uint32_t w = 64, h = 48;
  testing::FakeV4l2Device fake;
  fake.add_node("/dev/d", {.pixelformat = V4L2_PIX_FMT_Z16,
                           .width = w,
                           .height = h,
                           .bytes_per_line = 2 * w,
                           .size_image = 2 * w * h});
  fake.add_node("/dev/c", {.pixelformat = V4L2_PIX_FMT_YUYV,
                           .width = w,
                           .height = h,
                           .bytes_per_line = 2 * w,
                           .size_image = 2 * w * h});
  rt::FramePool pool({.slots = 4, .width = w, .height = h, .colour_channels = 3});
  rt::SpscRing<rt::FrameHandle> ring(2);  // never read: the drop path runs too
  V4l2RgbdDriverSettings s;
  s.depth_device = "/dev/d";
  s.colour_device = "/dev/c";
  s.width_px = w;
  s.height_px = h;
  s.realtime_thread = false;
  s.pin_cpu = false;
  V4l2RgbdDriver driver(s, pool, ring, fake);
  g_driver.store(&driver);
  driver.start();
  std::vector<std::uint8_t> depth(2 * w * h, 7), yuyv(2 * w * h, 128);
  auto wait_requeued = [&](std::size_t colour) {
    for (int i = 0; i < 5000 && (fake.queued("/dev/d") < 4 || fake.queued("/dev/c") < colour);
         ++i) {
      std::this_thread::sleep_for(1ms);
    }
  };
  constexpr int kFrames = 40;
  for (int f = 0; f < kFrames; ++f) {
    const std::int64_t t = 1'000'000'000 + f * 33'333'333LL;
    ASSERT_TRUE(fake.push_frame(
        "/dev/d",
        {.bytes = depth, .t_ns = t, .error_flag = f == 20, .skip_sequence = f == 30 ? 2u : 0u}));
    ASSERT_TRUE(fake.push_frame("/dev/c", {.bytes = yuyv, .t_ns = t}));
    if (f == 10) fake.spurious_wakeups("/dev/c", 2);
    wait_requeued(f == 20 ? 3 : 4);  // colour 20 waits for a partner: its depth was corrupt
  }
  const auto deadline = std::chrono::steady_clock::now() + 5s;
  while (driver.counters().rgbd.frames_read < kFrames - 1 &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(1ms);
  }
  const V4l2RgbdCounters c = driver.counters();
  driver.stop();
  g_driver.store(nullptr);
  EXPECT_EQ(c.rgbd.frames_read, static_cast<std::uint64_t>(kFrames - 1));  // one corrupt depth
  EXPECT_GT(c.rgbd.dropped_ring_full, 30u);
  EXPECT_EQ(c.corrupt_buffers, 1u);
  EXPECT_EQ(c.kernel_dropped, 2u);
  RecordProperty("warmup_allocations", std::to_string(g_warmup.load()));
  EXPECT_EQ(c.rgbd.losses, 0u);
  EXPECT_EQ(g_loop.load(), 0) << "operator new on the driver thread after the first two pairs";
  for (void* who : g_callers) {
    Dl_info info{};
    if (who != nullptr && ::dladdr(who, &info) != 0) {
      std::fprintf(
          stderr, "caller %s +0x%lx\n", info.dli_fname,
          static_cast<unsigned long>(static_cast<char*>(who) - static_cast<char*>(info.dli_fbase)));
    }
  }
  rt::FrameHandle hd;
  while (ring.try_pop(hd)) pool.release(hd);
}

}  // namespace
}  // namespace vigs::drivers
