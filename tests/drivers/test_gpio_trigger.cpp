// Frame sync: the gpio_trigger thread decodes kernel-format `struct gpioevent_data` records
// (linux/gpio.h, GPIO uAPI v1) written into a pipe, through libgpiod 1.6's own
// gpiod_line_event_read_fd_multiple (this kernel has no gpiochip); TriggerMatcher replaces frame
// stamps by their edges' with missing and extra edges; and the V4L2 driver (on its fake device)
// restamps its frames from the edges of a pipe.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/gpio.h>
#include <linux/videodev2.h>
#include <unistd.h>

#include <chrono>
#include <functional>
#include <thread>
#include <vector>

#include "drivers/common/trigger_matcher.hpp"
#include "drivers/gpio_trigger/gpio_trigger.hpp"
#include "drivers/v4l2/v4l2_rgbd_driver.hpp"
#include "fake_v4l2_device.hpp"
#include "io/json_text.hpp"
#include "tests/common/test_pipe.hpp"

namespace vigs::drivers {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;
constexpr std::int64_t kMs = 1'000'000;

bool wait_until(const std::function<bool()>& done, std::chrono::milliseconds limit = 5000ms) {
  const auto deadline = Clock::now() + limit;
  while (!done()) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(1ms);
  }
  return true;
}

struct Pipe : test::GpioEventPipe {
  void edge(std::int64_t t_ns, std::uint32_t id = GPIOEVENT_EVENT_RISING_EDGE) const {
    ASSERT_TRUE(write_edge(t_ns, id));
  }
};

GpioTriggerSettings test_settings() {
  GpioTriggerSettings s;
  s.realtime_thread = false;
  s.pin_cpu = false;
  return s;
}

TEST(GpioTrigger, DecodesKernelEventRecordsThroughLibgpiod) {
  Pipe p;
  ASSERT_GE(p.r, 0);
  rt::SpscRing<TriggerEdge> edges(16);
  rt::SpscRing<TriggerEdge> tap(2);
  GpioTrigger trigger(test_settings(), edges);
  trigger.set_tap(&tap);
  trigger.start_with_event_fd(p.r);
  const std::int64_t t0 = 7'000'000'123;
  for (int i = 0; i < 5; ++i) p.edge(t0 + i * 33 * kMs);
  p.edge(t0 + 200 * kMs, GPIOEVENT_EVENT_FALLING_EDGE);  // counted, ignored
  p.edge(t0 + 10 * kMs);                                 // before the last edge: dropped
  ASSERT_TRUE(wait_until([&] { return trigger.counters().non_monotonic == 1; }));
  GpioTriggerCounters c = trigger.counters();
  EXPECT_EQ(c.rising, 5u);
  EXPECT_EQ(c.falling, 1u);
  EXPECT_EQ(c.pushed, 5u);
  EXPECT_EQ(c.tap_dropped, 3u);  // the tap holds 2: a full tap drops, the driver's ring does not
  for (int i = 0; i < 5; ++i) {
    TriggerEdge e;
    ASSERT_TRUE(edges.try_pop(e));
    EXPECT_EQ(e.t_ns, t0 + i * 33 * kMs) << "the kernel's nanosecond stamp, unchanged";
    EXPECT_EQ(e.sequence, static_cast<std::uint64_t>(i));
  }
  // A short record (not what the kernel writes) is a read error, not an edge.
  const char half[8] = {};
  ASSERT_EQ(::write(p.w, half, sizeof half), 8);
  ASSERT_TRUE(wait_until([&] { return trigger.counters().read_errors == 1; }));
  EXPECT_EQ(trigger.counters().rising, 5u);
  // The writer going away ends the source and the thread.
  ::close(p.w);
  p.w = -1;
  ASSERT_TRUE(wait_until([&] { return trigger.counters().source_closed; }));
  trigger.stop();
}

TEST(GpioTrigger, StopReturnsWhileNoEdgeComes) {
  Pipe p;
  rt::SpscRing<TriggerEdge> edges(4);
  GpioTrigger trigger(test_settings(), edges);
  trigger.start_with_event_fd(p.r);
  std::this_thread::sleep_for(50ms);
  const auto t0 = Clock::now();
  trigger.stop();
  const double stop_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  EXPECT_LT(stop_ms, 1000.0);
  EXPECT_FALSE(trigger.running());
}

TEST(GpioTrigger, AMissingChipIsAnErrorNamingIt) {
  rt::SpscRing<TriggerEdge> edges(4);
  GpioTriggerSettings s = test_settings();
  s.chip = "/dev/gpiochip-not-there";
  s.line = 7;
  GpioTrigger trigger(s, edges);
  try {
    trigger.start();
    FAIL() << "start() opened a missing chip";
  } catch (const GpioTriggerError& e) {
    EXPECT_NE(std::string(e.what()).find("line 7 of '/dev/gpiochip-not-there'"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(trigger.running());
}

TEST(TriggerMatcher, RestampsFramesWithMissingAndExtraEdges) {
  rt::SpscRing<TriggerEdge> edges(64);
  // Frames are stamped 5 ms after their exposure's edge, +-0.4 ms jitter; tolerance 2 ms.
  TriggerMatcher m(edges, {.tolerance_ns = 2 * kMs, .offset_ns = 5 * kMs});
  const std::int64_t period = 50 * kMs;
  auto edge_at = [&](int i) { return std::int64_t{1'000} * kMs + i * period; };
  // Edges 0..9, except 3 (missing edge); plus a spurious edge between 6 and 7 (extra edge).
  for (int i = 0; i < 10; ++i) {
    if (i != 3) {
      ASSERT_TRUE(edges.try_push(TriggerEdge{edge_at(i), 0}));
    }
    if (i == 6) {
      ASSERT_TRUE(edges.try_push(TriggerEdge{edge_at(6) + 20 * kMs, 0}));
    }
  }
  std::vector<std::optional<std::int64_t>> got;
  for (int i = 0; i < 10; ++i) {
    if (i == 8) continue;  // frame 8 never came (its edge is extra)
    const std::int64_t jitter = (i % 3 - 1) * 400'000;
    got.push_back(m.match(edge_at(i) + 5 * kMs + jitter));
  }
  const int frames[] = {0, 1, 2, 3, 4, 5, 6, 7, 9};
  for (std::size_t k = 0; k < got.size(); ++k) {
    const int i = frames[k];
    if (i == 3) {
      EXPECT_FALSE(got[k].has_value()) << "frame 3 has no edge: it keeps its own stamp";
    } else {
      ASSERT_TRUE(got[k].has_value()) << "frame " << i;
      EXPECT_EQ(*got[k], edge_at(i)) << "frame " << i;
    }
  }
  m.finish();
  const TriggerMatchCounters c = m.counters();
  EXPECT_EQ(c.matched, 8u);
  EXPECT_EQ(c.frames_without_edge, 1u);
  EXPECT_EQ(c.edges_without_frame, 2u);  // the spurious edge and frame 8's
}

TEST(TriggerMatcher, AFullWindowDropsItsOldestEdgeCounted) {
  rt::SpscRing<TriggerEdge> edges(64);
  TriggerMatcher m(edges, {.tolerance_ns = 1 * kMs, .offset_ns = 0});
  for (int i = 0; i < 40; ++i) ASSERT_TRUE(edges.try_push(TriggerEdge{(i + 1) * 10 * kMs, 0}));
  // A frame at the 40th edge: the 8 oldest fell out of the 32-edge window, 31 more are too old.
  EXPECT_EQ(m.match(400 * kMs), std::optional<std::int64_t>(400 * kMs));
  EXPECT_EQ(m.counters().edges_without_frame, 39u);
}

// stats.json's "trigger" and "trigger_match" objects: every counter under its own name.
TEST(GpioTrigger, CountersAsJsonNameEveryCounter) {
  const GpioTriggerCounters t{.rising = 1,
                              .falling = 2,
                              .pushed = 3,
                              .dropped_ring_full = 4,
                              .tap_dropped = 5,
                              .read_errors = 6,
                              .non_monotonic = 7,
                              .source_closed = true};
  EXPECT_EQ(io::json_line(to_json_value(t)),
            R"({"rising": 1, "falling": 2, "pushed": 3, "dropped_ring_full": 4, "tap_dropped": 5, )"
            R"("read_errors": 6, "non_monotonic": 7, "source_closed": true})");
  const TriggerMatchCounters m{.matched = 8, .frames_without_edge = 9, .edges_without_frame = 10};
  EXPECT_EQ(io::json_line(to_json_value(m)),
            R"({"matched": 8, "frames_without_edge": 9, "edges_without_frame": 10})");
}

TEST(GpioTrigger, V4l2FramesTakeTheirEdgeStampsFromThePipe) {
  constexpr std::uint32_t w = 16, h = 12;
  testing::FakeV4l2Device fake;
  fake.add_node("/dev/d", {.pixelformat = V4L2_PIX_FMT_Z16,
                           .width = w,
                           .height = h,
                           .bytes_per_line = 2 * w,
                           .size_image = 2 * w * h});
  fake.add_node("/dev/c", {.pixelformat = V4L2_PIX_FMT_GREY,
                           .width = w,
                           .height = h,
                           .bytes_per_line = w,
                           .size_image = w * h});
  rt::FramePool pool({.slots = 8, .width = w, .height = h, .colour_channels = 1});
  rt::SpscRing<rt::FrameHandle> ring(8);
  V4l2RgbdDriverSettings s;
  s.depth_device = "/dev/d";
  s.colour_device = "/dev/c";
  s.colour_format = V4l2PixelFormat::kGrey;
  s.width_px = w;
  s.height_px = h;
  s.realtime_thread = false;
  s.pin_cpu = false;
  Pipe p;
  rt::SpscRing<TriggerEdge> edges(16);
  GpioTrigger trigger(test_settings(), edges);
  TriggerMatcher matcher(edges, {.tolerance_ns = 3 * kMs, .offset_ns = 8 * kMs});
  V4l2RgbdDriver driver(s, pool, ring, fake);
  driver.set_trigger(&matcher);
  trigger.start_with_event_fd(p.r);
  driver.start();
  std::vector<std::uint8_t> depth(2 * w * h, 1), grey(w * h, 2);
  const std::int64_t t0 = 3'000'000'000;
  for (int f = 0; f < 4; ++f) {
    const std::int64_t t_edge = t0 + f * 33'333'333 + 111;
    if (f != 2) p.edge(t_edge);  // frame 2's edge is missing
    ASSERT_TRUE(wait_until([&] { return trigger.counters().rising == (f < 2 ? f + 1u : f + 0u); }));
    const std::int64_t t_frame = t_edge + 8 * kMs + 250'000;  // arrives 8.25 ms later
    ASSERT_TRUE(fake.push_frame("/dev/d", {.bytes = depth, .t_ns = t_frame}));
    ASSERT_TRUE(fake.push_frame("/dev/c", {.bytes = grey, .t_ns = t_frame}));
    ASSERT_TRUE(wait_until([&] { return driver.counters().rgbd.delivered == f + 1u; }));
  }
  std::vector<std::int64_t> stamps;
  rt::FrameHandle hd;
  while (ring.try_pop(hd)) {
    stamps.push_back(pool.frame(hd).t_ns);
    pool.release(hd);
  }
  ASSERT_EQ(stamps.size(), 4u);
  for (int f = 0; f < 4; ++f) {
    const std::int64_t t_edge = t0 + f * 33'333'333 + 111;
    const std::int64_t t_frame = t_edge + 8 * kMs + 250'000;
    // Frames with an edge carry its exact nanosecond stamp; frame 2 keeps its kernel stamp (us).
    EXPECT_EQ(stamps[f], f == 2 ? t_frame - t_frame % 1000 : t_edge) << "frame " << f;
  }
  driver.stop();
  trigger.stop();
  const TriggerMatchCounters c = matcher.counters();
  EXPECT_EQ(c.matched, 3u);
  EXPECT_EQ(c.frames_without_edge, 1u);
}

}  // namespace
}  // namespace vigs::drivers
