// Driver-side costs, each beside a baseline measured in the same run:
//  - BM_RecorderFrame: the recorder's cost per 720x480 RGB-D frame plus its 10 IMU samples (20 Hz
//    camera, 200 Hz IMU) at the default zstd level (3): encode Image/CameraInfo/Imu messages into
//    zstd chunks of an MCAP file. Baseline BM_PlainWrite: write(2) of the same raw bytes.
//    Frame content: a 720x480 crop of kodim10.png and a smooth depth ramp with noise.
//  - BM_V4l2FrameToRing: the V4L2 driver's frame-to-ring latency, kernel stamp (taken when the fake
//    device completes the buffer) to the consumer's pop: poll wake-up, DQBUF, pairing, Z16 copy,
//    YUYV -> rgb8 through libv4lconvert, push. Baseline BM_ConvertYuyv720x480: the conversion
//    alone on the same buffer.
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <linux/videodev2.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "drivers/v4l2/v4l2_converter.hpp"
#include "drivers/v4l2/v4l2_rgbd_driver.hpp"
#include "fake_v4l2_device.hpp"
#include "io/image_io.hpp"
#include "record/recorder.hpp"
#include "rt/clock.hpp"

namespace {

using namespace vigs;
constexpr std::uint32_t kW = 720, kH = 480;

struct Content {
  std::vector<std::uint8_t> rgb;
  std::vector<std::uint16_t> depth;
  std::vector<std::uint8_t> yuyv;
};

const Content& content() {
  static const Content c = [] {
    Content k;
    const ImageU8 full = io::read_rgb(std::string(VIGS_SHARED_DATA_DIR) + "/images/kodim10.png");
    k.rgb.resize(std::size_t{kW} * kH * 3);
    for (std::uint32_t y = 0; y < kH; ++y) {
      for (std::uint32_t x = 0; x < kW; ++x) {
        for (int ch = 0; ch < 3; ++ch) {
          k.rgb[(y * kW + x) * 3 + ch] = full.at(static_cast<int>(x), static_cast<int>(y), ch);
        }
      }
    }
    k.depth.resize(std::size_t{kW} * kH);
    std::uint32_t lcg = 1;
    for (std::uint32_t y = 0; y < kH; ++y) {
      for (std::uint32_t x = 0; x < kW; ++x) {
        lcg = lcg * 1664525u + 1013904223u;
        k.depth[y * kW + x] = static_cast<std::uint16_t>(800 + 3 * x + 2 * y + (lcg >> 29));
      }
    }
    k.yuyv.resize(std::size_t{kW} * kH * 2);
    for (std::size_t i = 0; i < k.yuyv.size(); ++i) {
      k.yuyv[i] = i % 2 == 0 ? k.rgb[(i / 2) * 3 + 1] : 128;  // Y from green, neutral chroma
    }
    return k;
  }();
  return c;
}

std::string bench_path(const char* name) {
  return "/tmp/vigs_bench_" + std::to_string(::getpid()) + "_" + name;
}

void BM_RecorderFrame(benchmark::State& state) {
  const Content& c = content();
  rt::FramePool pool({.slots = 2, .width = kW, .height = kH, .colour_channels = 3});
  rt::SpscRing<rt::FrameHandle> tap(2);
  rt::SpscRing<ImuSample> imu(64);
  const std::string path = bench_path("rec.mcap");
  record::Recorder rec(path);
  rec.add_frames(pool, tap, {415.7, 415.7, 360, 240});
  rec.add_imu(imu);
  rec.open();
  std::int64_t t = 1'000'000'000;
  for (auto _ : state) {
    rt::FrameHandle h = pool.acquire();
    rt::Frame& f = pool.frame(h);
    std::memcpy(f.colour.data(), c.rgb.data(), c.rgb.size());
    std::memcpy(f.depth.data(), c.depth.data(), c.depth.size() * 2);
    f.t_ns = t;
    (void)tap.try_push(h);
    for (int k = 0; k < 10; ++k) {
      ImuSample s;
      s.t_ns = t + k * 5'000'000;
      s.accel_mps2[2] = 9.81;
      (void)imu.try_push(s);
    }
    rec.drain_once();
    t += 50'000'000;
  }
  rec.stop();
  const record::RecorderStats s = rec.stats();
  state.counters["MB_per_frame_on_disk"] =
      static_cast<double>(s.bytes_written) / 1e6 / static_cast<double>(state.iterations());
  state.counters["raw_MB_per_frame"] =
      static_cast<double>(c.rgb.size() + c.depth.size() * 2 + 10 * 64) / 1e6;
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(c.rgb.size() + c.depth.size() * 2));
  ::unlink(path.c_str());
}
BENCHMARK(BM_RecorderFrame)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_PlainWrite(benchmark::State& state) {
  const Content& c = content();
  const std::string path = bench_path("plain.bin");
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  std::vector<std::uint8_t> imu_bytes(10 * 64, 1);
  for (auto _ : state) {
    benchmark::DoNotOptimize(::write(fd, c.rgb.data(), c.rgb.size()));
    benchmark::DoNotOptimize(::write(fd, c.depth.data(), c.depth.size() * 2));
    benchmark::DoNotOptimize(::write(fd, imu_bytes.data(), imu_bytes.size()));
  }
  ::close(fd);
  ::unlink(path.c_str());
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(c.rgb.size() + c.depth.size() * 2));
}
BENCHMARK(BM_PlainWrite)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_ConvertYuyv720x480(benchmark::State& state) {
  const Content& c = content();
  drivers::testing::FakeV4l2Device fake;
  fake.add_node("/dev/c", {.pixelformat = V4L2_PIX_FMT_YUYV,
                           .width = kW,
                           .height = kH,
                           .bytes_per_line = 2 * kW,
                           .size_image = 2 * kW * kH});
  const int fd = fake.open("/dev/c");
  drivers::V4l2Converter conv(fake, fd, drivers::V4l2PixelFormat::kYuyv, kW, kH, 2 * kW);
  std::vector<std::uint8_t> rgb(std::size_t{kW} * kH * 3);
  for (auto _ : state) benchmark::DoNotOptimize(conv.to_rgb8(c.yuyv, rgb));
}
BENCHMARK(BM_ConvertYuyv720x480)->Unit(benchmark::kMicrosecond);

void BM_V4l2FrameToRing(benchmark::State& state) {
  const Content& c = content();
  drivers::testing::FakeV4l2Device fake;
  fake.add_node("/dev/d", {.pixelformat = V4L2_PIX_FMT_Z16,
                           .width = kW,
                           .height = kH,
                           .bytes_per_line = 2 * kW,
                           .size_image = 2 * kW * kH});
  fake.add_node("/dev/c", {.pixelformat = V4L2_PIX_FMT_YUYV,
                           .width = kW,
                           .height = kH,
                           .bytes_per_line = 2 * kW,
                           .size_image = 2 * kW * kH});
  rt::FramePool pool({.slots = 6, .width = kW, .height = kH, .colour_channels = 3});
  rt::SpscRing<rt::FrameHandle> ring(4);
  drivers::V4l2RgbdDriverSettings s;
  s.depth_device = "/dev/d";
  s.colour_device = "/dev/c";
  s.width_px = kW;
  s.height_px = kH;
  s.realtime_thread = false;  // unprivileged benchmark: normal scheduling (stated)
  s.pin_cpu = false;
  drivers::V4l2RgbdDriver driver(s, pool, ring, fake);
  driver.start();
  const auto* depth = reinterpret_cast<const std::uint8_t*>(c.depth.data());
  const std::span<const std::uint8_t> depth_bytes(depth, c.depth.size() * 2);
  std::vector<double> latency_us;
  latency_us.reserve(100000);
  for (auto _ : state) {
    while (fake.queued("/dev/d") < 4 || fake.queued("/dev/c") < 4) std::this_thread::yield();
    const std::int64_t t = rt::monotonic_ns();
    (void)fake.push_frame("/dev/c", {.bytes = c.yuyv, .t_ns = t});
    (void)fake.push_frame("/dev/d", {.bytes = depth_bytes, .t_ns = t});
    rt::FrameHandle h;
    while (!ring.try_pop(h)) {
    }
    const std::int64_t t_pop = rt::monotonic_ns();
    latency_us.push_back(rt::ns_to_us(t_pop - pool.frame(h).t_ns));
    pool.release(h);
  }
  driver.stop();
  std::sort(latency_us.begin(), latency_us.end());
  if (!latency_us.empty()) {
    state.counters["p50_us"] = latency_us[latency_us.size() / 2];
    state.counters["p99_us"] = latency_us[latency_us.size() * 99 / 100];
  }
}
BENCHMARK(BM_V4l2FrameToRing)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
