// The OpenNI2 RGB-D driver against real OpenNI2 playback (Debian libopenni2-0, OniFile driver):
// clips with known per-frame depth and colour patterns are written by the project's
// OniClipWriter, played by the driver (Device::open(path), setSpeed(-1)) on its own thread and
// consumed from the FrameHandle ring by a test thread.
#include <OpenNI.h>
#include <gtest/gtest.h>
#include <sys/types.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "../common/temp_files.hpp"
#include "drivers/openni2/openni2_driver.hpp"
#include "io/oni/oni_clip_writer.hpp"
#include "rt/frame_pool.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::drivers {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

constexpr std::uint32_t kW = 64, kH = 48;

std::uint16_t depth_at(std::uint64_t f, std::uint32_t x, std::uint32_t y) {
  return static_cast<std::uint16_t>(400 + 1000 * f + 41 * y + x);  // mm
}
std::uint8_t rgb_at(std::uint64_t f, std::uint32_t x, std::uint32_t y, int c) {
  return static_cast<std::uint8_t>(c == 0 ? 3 * x + 7 * f : c == 1 ? 5 * y + 11 * f : x ^ y ^ f);
}

// Removed when the test program exits, passed or failed.
std::string temp_path(const std::string& name) {
  static vigs::test::TempFiles files("openni2");
  return files.path(name);
}

std::string write_clip(const std::string& name, int frames, std::uint32_t w = kW,
                       std::uint32_t h = kH, std::uint32_t fps = 30) {
  const std::string path = temp_path(name);
  io::oni::OniClipWriter writer(path, {w, h, fps});
  std::vector<std::uint16_t> depth(std::size_t{w} * h);
  std::vector<std::uint8_t> rgb(std::size_t{w} * h * 3);
  for (int f = 0; f < frames; ++f) {
    for (std::uint32_t y = 0; y < h; ++y) {
      for (std::uint32_t x = 0; x < w; ++x) {
        depth[y * w + x] = depth_at(static_cast<std::uint64_t>(f), x, y);
        for (int c = 0; c < 3; ++c) {
          rgb[(y * w + x) * 3 + c] = rgb_at(static_cast<std::uint64_t>(f), x, y, c);
        }
      }
    }
    writer.add_frame(depth, rgb);
  }
  writer.close();
  return path;
}

Openni2DriverSettings settings_for(const std::string& path, std::uint32_t w = kW,
                                   std::uint32_t h = kH) {
  Openni2DriverSettings s;
  s.uri = path;
  s.width_px = w;
  s.height_px = h;
  s.rate_hz = 30.0;
  s.realtime_thread = false;  // tests run unprivileged; the table's spec would only warn
  s.pin_cpu = false;
  return s;
}

rt::FramePoolSettings pool_for(std::uint32_t slots, std::uint32_t w = kW, std::uint32_t h = kH) {
  return {.slots = slots, .width = w, .height = h, .colour_channels = 3};
}

// Pixels of a slot that differ from frame f's pattern.
int bad_pixels(const rt::Frame& frame, std::uint64_t f, std::uint32_t w = kW,
               std::uint32_t h = kH) {
  int bad = 0;
  for (std::uint32_t y = 0; y < h; ++y) {
    for (std::uint32_t x = 0; x < w; ++x) {
      bad += frame.depth[y * w + x] != depth_at(f, x, y);
      for (int c = 0; c < 3; ++c) bad += frame.colour[(y * w + x) * 3 + c] != rgb_at(f, x, y, c);
    }
  }
  return bad;
}

bool wait_until(const std::function<bool()>& done, std::chrono::milliseconds limit) {
  const auto deadline = Clock::now() + limit;
  while (!done()) {
    if (Clock::now() > deadline) return false;
    std::this_thread::sleep_for(1ms);
  }
  return true;
}

// What the consumer thread saw.
struct Received {
  std::vector<std::uint64_t> sequence;
  std::vector<std::int64_t> t_ns;
  std::vector<std::int64_t> arrival_ns;
  int bad_pixels = 0;
  bool end_marker = false;
};

// Pops until the end-of-stream marker (or `limit`), checks pixels against the frame's pattern
// (sequence == clip frame when nothing was dropped before it) and releases each slot.
Received consume(rt::SpscRing<rt::FrameHandle>& ring, rt::FramePool& pool,
                 std::chrono::milliseconds limit, std::chrono::microseconds per_frame = 0us,
                 std::uint32_t w = kW, std::uint32_t h = kH) {
  Received r;
  const auto deadline = Clock::now() + limit;
  while (Clock::now() < deadline) {
    rt::FrameHandle handle;
    if (!ring.try_pop(handle)) {
      std::this_thread::sleep_for(100us);
      continue;
    }
    if (!handle.valid()) {
      r.end_marker = true;
      break;
    }
    const rt::Frame& frame = pool.frame(handle);
    r.sequence.push_back(frame.sequence);
    r.t_ns.push_back(frame.t_ns);
    r.arrival_ns.push_back(frame.arrival_ns);
    r.bad_pixels += bad_pixels(frame, frame.sequence, w, h);
    pool.release(handle);
    if (per_frame > 0us) std::this_thread::sleep_for(per_frame);
  }
  return r;
}

class Openni2Driver : public ::testing::Test {
 protected:
  // One OpenNI2 context for the suite: the driver's own initialize()/shutdown() then only move
  // OpenNI2's reference count instead of reloading its device drivers for every test.
  static void SetUpTestSuite() {
    ASSERT_EQ(openni::OpenNI::initialize(), openni::STATUS_OK)
        << openni::OpenNI::getExtendedError();
  }
  static void TearDownTestSuite() { openni::OpenNI::shutdown(); }
};

TEST_F(Openni2Driver, EveryFrameArrivesInOrderWithExactPixelsAndDeviceSpacedStamps) {
  constexpr int kFrames = 12;
  const std::string path = write_clip("all.oni", kFrames);
  rt::FramePool pool(pool_for(kFrames + 2));  // room for every frame: nothing can drop
  rt::SpscRing<rt::FrameHandle> ring(16);
  drivers::Openni2Driver driver(settings_for(path), pool, ring);
  const auto t0 = Clock::now();
  driver.start();
  EXPECT_TRUE(driver.is_file());
  ASSERT_NE(driver.thread_status(), nullptr);
  Received got;
  std::thread consumer([&] { got = consume(ring, pool, 5000ms); });
  consumer.join();
  const double playback_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  RecordProperty("playback_ms", std::to_string(playback_ms));

  EXPECT_TRUE(got.end_marker);
  EXPECT_TRUE(driver.end_of_stream());
  ASSERT_EQ(got.sequence.size(), static_cast<std::size_t>(kFrames));
  for (int i = 0; i < kFrames; ++i) EXPECT_EQ(got.sequence[i], static_cast<std::uint64_t>(i));
  EXPECT_EQ(got.bad_pixels, 0);
  // Stamps keep the clip's device spacing (1/30 s, whole microseconds) on the host clock.
  for (int i = 1; i < kFrames; ++i) {
    const std::int64_t dt_ns = got.t_ns[i] - got.t_ns[i - 1];
    EXPECT_GE(dt_ns, 33'333'000) << "frame " << i;
    EXPECT_LE(dt_ns, 33'334'000) << "frame " << i;
  }
  const RgbdDriverCounters c = driver.counters();
  EXPECT_TRUE(c.end_of_stream);
  EXPECT_EQ(c.depth_read, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(c.colour_read, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(c.frames_read, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(c.delivered, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(c.dropped_ring_full, 0u);
  EXPECT_EQ(c.dropped_pool_empty, 0u);
  EXPECT_EQ(c.unpaired, 0u);
  EXPECT_EQ(c.size_mismatch, 0u);
  EXPECT_EQ(c.read_errors, 0u);
  driver.stop();
  EXPECT_FALSE(driver.running());
  EXPECT_EQ(pool.available(), pool.capacity());
}

// Real time (playback_speed 1, `vigs run --through-drivers`): like a sensor, the driver never
// hands over a frame before the time its stamp stands for, and over a clip of seconds the
// schedule does not drift. OpenNI2's own pacing (setSpeed(1)) fails this: at 20 Hz it sleeps 49
// whole ms from each frame, so frames near the end of a 4 s clip arrive tens of ms early.
TEST_F(Openni2Driver, RealTimePlaybackNeverDeliversAFrameBeforeItsStamp) {
  constexpr int kFrames = 80;  // 4 s at 20 Hz, the camera rate of the paper's data
  const std::string path = write_clip("realtime.oni", kFrames, kW, kH, 20);
  rt::FramePool pool(pool_for(8));
  rt::SpscRing<rt::FrameHandle> ring(8);
  Openni2DriverSettings settings = settings_for(path);
  settings.playback_speed = 1.0;
  drivers::Openni2Driver driver(settings, pool, ring);
  driver.start();
  Received got;
  std::thread consumer([&] { got = consume(ring, pool, 20000ms); });
  consumer.join();
  EXPECT_TRUE(got.end_marker);
  ASSERT_EQ(got.sequence.size(), static_cast<std::size_t>(kFrames));  // manual mode: none lost
  EXPECT_EQ(got.bad_pixels, 0);
  std::int64_t earliest_ns = INT64_MAX;
  for (int i = 0; i < kFrames; ++i) {
    EXPECT_EQ(got.sequence[i], static_cast<std::uint64_t>(i));
    earliest_ns = std::min(earliest_ns, got.arrival_ns[i] - got.t_ns[i]);
  }
  RecordProperty("earliest_arrival_minus_stamp_us", std::to_string(earliest_ns / 1000));
  EXPECT_GE(earliest_ns, -1'000'000)
      << "a frame arrived " << -earliest_ns / 1000 << " us before its stamp";
  // The last frame left after the clip's span (4 s), not before: no fast drift.
  EXPECT_GE(got.arrival_ns.back() - got.arrival_ns.front(),
            got.t_ns.back() - got.t_ns.front() - 1'000'000);
  EXPECT_EQ(driver.counters().playback_skipped, 0u);
  driver.stop();
}

TEST_F(Openni2Driver, FullRingDropsNewestCountsThemAndNeverBlocksTheDriver) {
  constexpr int kFrames = 10;
  const std::string path = write_clip("slow.oni", kFrames);
  rt::FramePool pool(pool_for(8));
  rt::SpscRing<rt::FrameHandle> ring(2);
  drivers::Openni2Driver driver(settings_for(path), pool, ring);
  driver.start();
  // Nobody consumes yet: a driver that waited for room would never reach the end of the clip.
  ASSERT_TRUE(wait_until([&] { return driver.end_of_stream(); }, 5000ms));
  const RgbdDriverCounters c = driver.counters();
  EXPECT_EQ(c.frames_read, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(c.delivered, 2u);
  EXPECT_EQ(c.dropped_ring_full, static_cast<std::uint64_t>(kFrames - 2));
  EXPECT_EQ(c.dropped_pool_empty, 0u);
  EXPECT_EQ(c.delivered + c.dropped_ring_full + c.dropped_pool_empty, c.frames_read);
  // Dropped frames gave their slots back at once: only the two queued ones are taken.
  EXPECT_EQ(pool.available(), pool.capacity() - 2);

  // A slow consumer now drains the two oldest frames, then the end marker.
  Received got;
  std::thread consumer([&] { got = consume(ring, pool, 5000ms, 20ms); });
  consumer.join();
  EXPECT_TRUE(got.end_marker);
  ASSERT_EQ(got.sequence.size(), 2u);
  EXPECT_EQ(got.sequence[0], 0u);
  EXPECT_EQ(got.sequence[1], 1u);
  EXPECT_EQ(got.bad_pixels, 0);
  driver.stop();
  EXPECT_EQ(pool.available(), pool.capacity());
}

TEST_F(Openni2Driver, EmptyPoolIsCountedWhileTheConsumerHoldsHandles) {
  constexpr int kFrames = 8;
  const std::string path = write_clip("pool.oni", kFrames);
  rt::FramePool pool(pool_for(3));
  rt::SpscRing<rt::FrameHandle> ring(16);
  drivers::Openni2Driver driver(settings_for(path), pool, ring);
  driver.start();
  std::vector<rt::FrameHandle> held;
  bool end_marker = false;
  std::thread consumer([&] {
    const auto deadline = Clock::now() + 5000ms;
    while (Clock::now() < deadline && !end_marker) {
      rt::FrameHandle h;
      if (!ring.try_pop(h)) {
        std::this_thread::sleep_for(100us);
      } else if (!h.valid()) {
        end_marker = true;
      } else {
        held.push_back(h);  // never released until the end: the pool runs dry
      }
    }
  });
  consumer.join();
  EXPECT_TRUE(end_marker);
  const RgbdDriverCounters c = driver.counters();
  EXPECT_EQ(c.frames_read, static_cast<std::uint64_t>(kFrames));
  EXPECT_EQ(c.delivered, 3u);
  EXPECT_EQ(c.dropped_pool_empty, static_cast<std::uint64_t>(kFrames - 3));
  EXPECT_EQ(c.dropped_ring_full, 0u);
  EXPECT_EQ(pool.exhausted(), static_cast<std::uint64_t>(kFrames - 3));
  ASSERT_EQ(held.size(), 3u);
  for (std::size_t i = 0; i < held.size(); ++i) {
    EXPECT_EQ(pool.frame(held[i]).sequence, i);
    EXPECT_EQ(bad_pixels(pool.frame(held[i]), i), 0);
    pool.release(held[i]);
  }
  driver.stop();
}

TEST_F(Openni2Driver, MissingFileIsAnErrorNamingIt) {
  const std::string path = temp_path("does_not_exist.oni");
  rt::FramePool pool(pool_for(2));
  rt::SpscRing<rt::FrameHandle> ring(2);
  drivers::Openni2Driver driver(settings_for(path), pool, ring);
  try {
    driver.start();
    FAIL() << "start() accepted a missing file";
  } catch (const Openni2Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(driver.running());
}

TEST_F(Openni2Driver, GarbageFileIsAnErrorNamingIt) {
  const std::string path = temp_path("garbage.oni");
  {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::uint32_t x = 12345;
    for (int i = 0; i < 4096; ++i) {
      x = x * 1664525u + 1013904223u;
      std::fputc(static_cast<int>(x >> 24), f);
    }
    std::fclose(f);
  }
  rt::FramePool pool(pool_for(2));
  rt::SpscRing<rt::FrameHandle> ring(2);
  drivers::Openni2Driver driver(settings_for(path), pool, ring);
  try {
    driver.start();
    FAIL() << "start() accepted a garbage file";
  } catch (const Openni2Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  EXPECT_FALSE(driver.running());
  // The driver is reusable after a failed start: a good clip plays.
  const std::string good = write_clip("after_garbage.oni", 2);
  drivers::Openni2Driver again(settings_for(good), pool, ring);
  again.start();
  EXPECT_TRUE(wait_until([&] { return again.end_of_stream(); }, 5000ms));
  EXPECT_EQ(again.counters().delivered, 2u);
  again.stop();
}

TEST_F(Openni2Driver, ClipOfAnotherSizeIsAnErrorNamingBothSizes) {
  const std::string path = write_clip("small.oni", 2, 32, 24);
  rt::FramePool pool(pool_for(2));
  rt::SpscRing<rt::FrameHandle> ring(2);
  drivers::Openni2Driver driver(settings_for(path), pool, ring);
  try {
    driver.start();
    FAIL() << "start() accepted a 32x24 clip for a 64x48 camera";
  } catch (const Openni2Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find("32x24"), std::string::npos) << msg;
    EXPECT_NE(msg.find("64x48"), std::string::npos) << msg;
  }
  EXPECT_FALSE(driver.running());
}

TEST_F(Openni2Driver, PoolOfAnotherSizeIsRejectedAtConstruction) {
  rt::FramePool pool(pool_for(2, 32, 24));
  rt::SpscRing<rt::FrameHandle> ring(2);
  EXPECT_THROW(drivers::Openni2Driver(settings_for("x.oni"), pool, ring), std::invalid_argument);
}

TEST_F(Openni2Driver, StopMidStreamJoinsCleanly) {
  constexpr int kFrames = 60;
  constexpr std::uint32_t w = 160, h = 120;
  const std::string path = write_clip("long.oni", kFrames, w, h);
  rt::FramePool pool(pool_for(4, w, h));
  rt::SpscRing<rt::FrameHandle> ring(2);
  drivers::Openni2Driver driver(settings_for(path, w, h), pool, ring);
  std::atomic<bool> consumer_done{false};
  Received got;
  driver.start();
  std::thread consumer([&] {
    got = consume(ring, pool, 300ms, 0us, w, h);
    consumer_done = true;
  });
  ASSERT_TRUE(wait_until([&] { return driver.counters().frames_read >= 3; }, 5000ms));
  const auto t0 = Clock::now();
  driver.stop();
  const auto stop_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  EXPECT_LT(stop_ms, 1000.0);
  EXPECT_FALSE(driver.running());
  consumer.join();
  const RgbdDriverCounters c = driver.counters();
  EXPECT_EQ(c.delivered + c.dropped_ring_full + c.dropped_pool_empty, c.frames_read);
  EXPECT_LE(c.frames_read, static_cast<std::uint64_t>(kFrames));
  // What arrived arrived in order, intact.
  for (std::size_t i = 1; i < got.sequence.size(); ++i) {
    EXPECT_GT(got.sequence[i], got.sequence[i - 1]);
    EXPECT_GT(got.t_ns[i], got.t_ns[i - 1]);
  }
  EXPECT_EQ(got.bad_pixels, 0);
  // Drain what is still queued (the ring outlives the driver), then every slot is free again.
  rt::FrameHandle left;
  while (ring.try_pop(left)) pool.release(left);
  EXPECT_EQ(pool.available(), pool.capacity());
  RecordProperty("stopped_mid_stream", c.end_of_stream ? "no" : "yes");
  // stop() is idempotent, and the same driver starts again on the same clip with a new thread
  // (the OpenNI2 pthread_kill probe of the joined thread must not crash: pinned_stack_thread.hpp).
  driver.stop();
  driver.start();
  EXPECT_TRUE(wait_until([&] { return driver.end_of_stream(); }, 5000ms));
  driver.stop();
  while (ring.try_pop(left)) pool.release(left);
  // And another driver on another clip.
  rt::FramePool pool2(pool_for(4));
  rt::SpscRing<rt::FrameHandle> ring2(4);
  drivers::Openni2Driver again(settings_for(write_clip("again.oni", 3)), pool2, ring2);
  again.start();
  EXPECT_TRUE(wait_until([&] { return again.end_of_stream(); }, 5000ms));
  EXPECT_EQ(again.counters().frames_read, 3u);
  again.stop();
}

TEST_F(Openni2Driver, StopReturnsWhileTheEndMarkerWaitsForRoom) {
  const std::string path = write_clip("marker.oni", 4);
  rt::FramePool pool(pool_for(4));
  rt::SpscRing<rt::FrameHandle> ring(2);
  drivers::Openni2Driver driver(settings_for(path), pool, ring);
  driver.start();
  ASSERT_TRUE(wait_until([&] { return driver.end_of_stream(); }, 5000ms));
  // The ring holds two frames and nobody reads: the thread retries the end marker until stop().
  EXPECT_EQ(ring.size(), 2u);
  const auto t0 = Clock::now();
  driver.stop();
  const double stop_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  EXPECT_LT(stop_ms, 1000.0);
  EXPECT_EQ(ring.size(), 2u);  // no marker was forced in
  rt::FrameHandle h;
  while (ring.try_pop(h)) pool.release(h);
  EXPECT_EQ(pool.available(), pool.capacity());
}

// Cuts a clip file to its first half (the test's own truncation, as a copy cut short would be).
void cut_in_half(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  ASSERT_NE(f, nullptr);
  std::vector<char> bytes(1 << 22);
  const std::size_t n = std::fread(bytes.data(), 1, bytes.size(), f);
  std::fclose(f);
  ASSERT_GT(n, 0u);
  ASSERT_LT(n, bytes.size());
  ASSERT_EQ(::truncate(path.c_str(), static_cast<off_t>(n / 2)), 0);
}

// The clip frame a slot holds, from its depth pattern (depth_at(f, 0, 0) = 400 + 1000 f).
std::uint64_t clip_frame_of(const rt::Frame& frame) {
  return (frame.depth[0] - 400u) / 1000u;
}

TEST_F(Openni2Driver, TruncatedClipEndsWithAClearErrorInsteadOfAHang) {
  // OpenNI2's player spins at 100 % CPU at the end of a clip cut short and never delivers the
  // frames the header promises: the progress watchdog ends the stream, naming the file.
  constexpr int kFrames = 20;
  const std::string path = write_clip("truncated.oni", kFrames);
  cut_in_half(path);
  rt::FramePool pool(pool_for(kFrames + 2));
  rt::SpscRing<rt::FrameHandle> ring(32);
  Openni2DriverSettings s = settings_for(path);
  s.frame_timeout_ms = 400;
  drivers::Openni2Driver driver(s, pool, ring);
  driver.start();
  Received got;
  const auto t0 = Clock::now();
  std::thread consumer([&] { got = consume(ring, pool, 10000ms); });
  consumer.join();
  const double end_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  EXPECT_LT(end_ms, 5000.0);
  EXPECT_TRUE(got.end_marker);
  EXPECT_TRUE(driver.end_of_stream());
  EXPECT_EQ(driver.state(), DeviceState::kFailed);
  EXPECT_EQ(driver.fault(), DeviceFault::kFrameTimeout);
  const std::string msg = driver.fault_message();
  EXPECT_NE(msg.find(path), std::string::npos) << msg;
  EXPECT_NE(msg.find("no progress"), std::string::npos) << msg;
  EXPECT_NE(msg.find("of 20 depth frames"), std::string::npos) << msg;
  // The frames before the cut arrived intact and in order: nothing played is lost.
  EXPECT_GE(got.sequence.size(), 5u);
  EXPECT_LT(got.sequence.size(), static_cast<std::size_t>(kFrames));
  for (std::size_t i = 0; i < got.sequence.size(); ++i) EXPECT_EQ(got.sequence[i], i);
  EXPECT_EQ(got.bad_pixels, 0);
  const RgbdDriverCounters c = driver.counters();
  EXPECT_EQ(c.frame_timeouts, 1u);
  EXPECT_EQ(c.losses, 1u);
  EXPECT_EQ(c.reopens, 0u);  // a clip is not reopened by default
  EXPECT_EQ(c.delivered, got.sequence.size());
  driver.stop();
  EXPECT_EQ(pool.available(), pool.capacity());
}

TEST_F(Openni2Driver, DeviceThatAppearsLaterIsOpenedWithBackoff) {
  constexpr int kFrames = 5;
  const std::string path = temp_path("later.oni");
  std::remove(path.c_str());
  rt::FramePool pool(pool_for(kFrames + 2));
  rt::SpscRing<rt::FrameHandle> ring(16);
  Openni2DriverSettings s = settings_for(path);
  s.wait_for_device = true;
  s.reopen_files = true;
  drivers::Openni2Driver driver(s, pool, ring);
  driver.start();  // does not throw: the thread keeps trying
  ASSERT_TRUE(wait_until([&] { return driver.counters().open_failures >= 2; }, 5000ms));
  EXPECT_EQ(driver.state(), DeviceState::kOpening);
  EXPECT_FALSE(driver.end_of_stream());
  EXPECT_EQ(write_clip("later.oni", kFrames), path);  // atomically renamed into place
  Received got;
  std::thread consumer([&] { got = consume(ring, pool, 10000ms); });
  consumer.join();
  EXPECT_TRUE(got.end_marker);
  EXPECT_EQ(driver.fault(), DeviceFault::kNone);
  ASSERT_EQ(got.sequence.size(), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(got.bad_pixels, 0);
  const RgbdDriverCounters c = driver.counters();
  EXPECT_EQ(c.opens, 1u);
  EXPECT_GE(c.open_failures, 2u);
  EXPECT_EQ(c.losses, 0u);
  driver.stop();
}

TEST_F(Openni2Driver, LostStreamIsReopenedWhenTheDeviceComesBack) {
  // A device that goes away mid-stream and comes back: the path first holds a clip cut short
  // (its playback stalls, as a camera that stops sending does), then a whole clip is renamed
  // over it. The driver loses the stream, closes, reopens by path with backoff and plays the
  // new clip to its end, with fresh stamps and the frame counter running on.
  constexpr int kFrames = 8;
  const std::string path = write_clip("comes_back.oni", 16);
  cut_in_half(path);
  rt::FramePool pool(pool_for(40));
  rt::SpscRing<rt::FrameHandle> ring(64);
  Openni2DriverSettings s = settings_for(path);
  s.frame_timeout_ms = 300;
  s.reopen_files = true;
  drivers::Openni2Driver driver(s, pool, ring);
  driver.start();
  ASSERT_TRUE(wait_until([&] { return driver.counters().losses >= 1; }, 5000ms));
  EXPECT_FALSE(driver.end_of_stream());
  EXPECT_EQ(write_clip("comes_back.oni", kFrames), path);
  std::vector<std::uint64_t> clip_frames;
  Received got;
  std::thread consumer([&] {
    const auto deadline = Clock::now() + 15000ms;
    while (Clock::now() < deadline) {
      rt::FrameHandle h;
      if (!ring.try_pop(h)) {
        std::this_thread::sleep_for(100us);
        continue;
      }
      if (!h.valid()) {
        got.end_marker = true;
        break;
      }
      const rt::Frame& f = pool.frame(h);
      clip_frames.push_back(clip_frame_of(f));
      got.sequence.push_back(f.sequence);
      got.t_ns.push_back(f.t_ns);
      got.bad_pixels += bad_pixels(f, clip_frame_of(f));
      pool.release(h);
    }
  });
  consumer.join();
  EXPECT_TRUE(got.end_marker);
  EXPECT_EQ(driver.state(), DeviceState::kEnded);
  EXPECT_EQ(driver.fault(), DeviceFault::kNone);
  EXPECT_EQ(got.bad_pixels, 0);
  // The whole new clip arrived last, in order.
  ASSERT_GE(clip_frames.size(), static_cast<std::size_t>(kFrames + 1));
  for (int i = 0; i < kFrames; ++i) {
    EXPECT_EQ(clip_frames[clip_frames.size() - kFrames + i], static_cast<std::uint64_t>(i));
  }
  for (std::size_t i = 1; i < got.sequence.size(); ++i) {
    EXPECT_GT(got.sequence[i], got.sequence[i - 1]);
    EXPECT_GT(got.t_ns[i], got.t_ns[i - 1]);
  }
  const RgbdDriverCounters c = driver.counters();
  EXPECT_GE(c.reopens, 1u);
  EXPECT_EQ(c.opens, c.reopens + 1);
  EXPECT_GE(c.frame_timeouts, 1u);
  EXPECT_EQ(c.losses, c.frame_timeouts);
  EXPECT_EQ(c.delivered + c.dropped_ring_full + c.dropped_pool_empty, c.frames_read);
  driver.stop();
  EXPECT_EQ(pool.available(), pool.capacity());
}

}  // namespace
}  // namespace vigs::drivers
