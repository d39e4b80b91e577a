// Recording-layer benchmarks, each beside a baseline measured in the same run:
//   CDR encoding of a 720x480 rgb8 Image vs memcpy of its pixels; CDR encode/decode of an Image
//   and an Imu, the codecs' own archive vs Fast CDR's; MCAP writing of RGB-D + IMU
//   frames (zstd level 1 and 3) vs write(2) of the same bytes; MCAP reading (zstd) with and
//   without CRC checks vs read(2) of the uncompressed byte count.
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "io/mcap/mcap_reader.hpp"
#include "io/mcap/mcap_writer.hpp"
#include "io/ros_msgs/fastcdr_archive.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/typed_io.hpp"
#include "io/ros_msgs/visit_fields.hpp"

namespace {

using namespace vigs::io;

constexpr std::uint32_t kW = 720, kH = 480;

// A rendered-looking frame: smooth gradients plus a little deterministic noise.
ros_msgs::Image make_rgb(int frame) {
  ros_msgs::Image m;
  m.header.frame_id = "left_cam";
  m.width = kW;
  m.height = kH;
  m.encoding = "rgb8";
  m.step = kW * 3;
  m.data.resize(std::size_t{kW} * kH * 3);
  std::uint32_t s = 1234u + static_cast<std::uint32_t>(frame);
  for (std::uint32_t y = 0; y < kH; ++y) {
    for (std::uint32_t x = 0; x < kW; ++x) {
      s = s * 1664525u + 1013904223u;
      const std::size_t i = (std::size_t{y} * kW + x) * 3;
      m.data[i] = static_cast<std::uint8_t>((x + frame) / 3 + (s >> 30));
      m.data[i + 1] = static_cast<std::uint8_t>(y / 2 + ((s >> 28) & 3));
      m.data[i + 2] = static_cast<std::uint8_t>(((x / 16) ^ (y / 16)) * 8);
    }
  }
  return m;
}

ros_msgs::Image make_depth(int frame) {
  ros_msgs::Image m;
  m.header.frame_id = "left_cam";
  m.width = kW;
  m.height = kH;
  m.encoding = "16UC1";
  m.step = kW * 2;
  m.data.resize(std::size_t{kW} * kH * 2);
  for (std::uint32_t y = 0; y < kH; ++y) {
    for (std::uint32_t x = 0; x < kW; ++x) {
      const auto d = static_cast<std::uint16_t>(1500 + 3 * x + 2 * y + frame);
      std::memcpy(&m.data[(std::size_t{y} * kW + x) * 2], &d, 2);
    }
  }
  return m;
}

std::string bench_path(const char* name) {
  return (std::filesystem::temp_directory_path() /
          (std::string("vigs_bench_io_") + std::to_string(::getpid()) + "_" + name))
      .string();
}

void BM_CdrEncodeImage(benchmark::State& state) {
  const ros_msgs::Image img = make_rgb(0);
  std::vector<std::uint8_t> out;
  for (auto _ : state) {
    ros_msgs::encode(img, ros_msgs::Encoding::kCdr, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * img.data.size()));
}
BENCHMARK(BM_CdrEncodeImage);

// Fast CDR (libfastcdr, the CDR library of Fast DDS) against the codecs' own CDR archive, same
// field order (detail::Visit*): the comparison behind keeping the latter (BENCHMARKS.md).
template <class Msg, class Visit>
void fastcdr_encode(const Msg& m, Visit visit, std::vector<std::uint8_t>& out) {
  ros_msgs::detail::SizeBound bound;
  visit(bound, m);
  out.clear();
  out.resize(bound.bytes);
  ros_msgs::detail::FastCdrEncoder ar(out);
  visit(ar, m);
  ar.finish();
}

ros_msgs::Imu make_imu() {
  ros_msgs::Imu m;
  m.header.frame_id = "imu";
  m.header.stamp = {12, 345};
  m.orientation = {0.1, 0.2, 0.3, 0.9};
  m.angular_velocity = {0.01, -0.02, 0.03};
  m.linear_acceleration = {0.1, 9.81, -0.2};
  for (int i = 0; i < 9; ++i) m.orientation_covariance[i] = 1e-3 * i;
  return m;
}

void BM_CdrEncodeImageFastCdr(benchmark::State& state) {
  const ros_msgs::Image img = make_rgb(0);
  std::vector<std::uint8_t> out;
  for (auto _ : state) {
    fastcdr_encode(img, ros_msgs::detail::VisitImage{}, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * img.data.size()));
}
BENCHMARK(BM_CdrEncodeImageFastCdr);

void BM_CdrDecodeImage(benchmark::State& state) {
  std::vector<std::uint8_t> bytes;
  ros_msgs::encode(make_rgb(0), ros_msgs::Encoding::kCdr, bytes);
  ros_msgs::Image m;
  for (auto _ : state) {
    ros_msgs::decode(bytes, ros_msgs::Encoding::kCdr, m);
    benchmark::DoNotOptimize(m.data.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
}
BENCHMARK(BM_CdrDecodeImage);

void BM_CdrDecodeImageFastCdr(benchmark::State& state) {
  std::vector<std::uint8_t> bytes;
  ros_msgs::encode(make_rgb(0), ros_msgs::Encoding::kCdr, bytes);
  ros_msgs::Image m;
  for (auto _ : state) {
    ros_msgs::detail::FastCdrDecoder ar(bytes, "sensor_msgs/msg/Image");
    ros_msgs::detail::VisitImage{}(ar, m);
    ar.finish();
    benchmark::DoNotOptimize(m.data.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
}
BENCHMARK(BM_CdrDecodeImageFastCdr);

void BM_CdrEncodeImu(benchmark::State& state) {
  const ros_msgs::Imu imu = make_imu();
  std::vector<std::uint8_t> out;
  for (auto _ : state) {
    ros_msgs::encode(imu, ros_msgs::Encoding::kCdr, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_CdrEncodeImu);

void BM_CdrEncodeImuFastCdr(benchmark::State& state) {
  const ros_msgs::Imu imu = make_imu();
  std::vector<std::uint8_t> out;
  for (auto _ : state) {
    fastcdr_encode(imu, ros_msgs::detail::VisitImu{}, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_CdrEncodeImuFastCdr);

void BM_CdrDecodeImu(benchmark::State& state) {
  std::vector<std::uint8_t> bytes;
  ros_msgs::encode(make_imu(), ros_msgs::Encoding::kCdr, bytes);
  ros_msgs::Imu m;
  for (auto _ : state) {
    ros_msgs::decode(bytes, ros_msgs::Encoding::kCdr, m);
    benchmark::DoNotOptimize(&m);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_CdrDecodeImu);

void BM_CdrDecodeImuFastCdr(benchmark::State& state) {
  std::vector<std::uint8_t> bytes;
  ros_msgs::encode(make_imu(), ros_msgs::Encoding::kCdr, bytes);
  ros_msgs::Imu m;
  for (auto _ : state) {
    ros_msgs::detail::FastCdrDecoder ar(bytes, "sensor_msgs/msg/Imu");
    ros_msgs::detail::VisitImu{}(ar, m);
    ar.finish();
    benchmark::DoNotOptimize(&m);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_CdrDecodeImuFastCdr);

void BM_MemcpyImageBaseline(benchmark::State& state) {
  const ros_msgs::Image img = make_rgb(0);
  std::vector<std::uint8_t> out(img.data.size());
  for (auto _ : state) {
    std::memcpy(out.data(), img.data.data(), img.data.size());
    benchmark::DoNotOptimize(out.data());
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * img.data.size()));
}
BENCHMARK(BM_MemcpyImageBaseline);

// One iteration = one RGB-D frame pair + 10 IMU samples (20 Hz camera, 200 Hz IMU).
void BM_McapWriteRgbdFrame(benchmark::State& state) {
  const std::string path = bench_path("write.mcap");
  std::vector<ros_msgs::Image> rgb, depth;
  for (int f = 0; f < 8; ++f) {
    rgb.push_back(make_rgb(f));
    depth.push_back(make_depth(f));
  }
  mcap::McapWriterOptions options;
  options.zstd_level = static_cast<int>(state.range(0));
  std::uint64_t bytes = 0, frames = 0, file_bytes = 0;
  {
    mcap::McapWriter w(path, options);
    const auto c_rgb = ros_msgs::add_channel<ros_msgs::Image>(w, "/rgb");
    const auto c_depth = ros_msgs::add_channel<ros_msgs::Image>(w, "/depth");
    const auto c_imu = ros_msgs::add_channel<ros_msgs::Imu>(w, "/imu");
    std::vector<std::uint8_t> buf;
    ros_msgs::Imu imu;
    std::uint64_t t = 0;
    for (auto _ : state) {
      const std::size_t k = frames % rgb.size();
      ros_msgs::write_message(w, c_rgb, t, rgb[k], buf);
      bytes += buf.size();
      ros_msgs::write_message(w, c_depth, t, depth[k], buf);
      bytes += buf.size();
      for (int i = 0; i < 10; ++i) {
        ros_msgs::write_message(w, c_imu, t + i * 5'000'000ull, imu, buf);
        bytes += buf.size();
      }
      t += 50'000'000;
      ++frames;
    }
    w.close();
    file_bytes = w.stats().bytes_written;
  }
  std::filesystem::remove(path);
  state.SetBytesProcessed(static_cast<std::int64_t>(bytes));
  state.SetItemsProcessed(static_cast<std::int64_t>(frames));
  state.counters["compression_ratio"] =
      static_cast<double>(bytes) / static_cast<double>(std::max<std::uint64_t>(file_bytes, 1));
}
BENCHMARK(BM_McapWriteRgbdFrame)->Arg(1)->Arg(3)->Unit(benchmark::kMillisecond)->UseRealTime();

// Baseline: write(2) of the same uncompressed byte count per frame.
void BM_RawWriteRgbdFrameBaseline(benchmark::State& state) {
  const std::string path = bench_path("raw.bin");
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::vector<std::uint8_t> frame(make_rgb(0).data.size() + make_depth(0).data.size() + 10 * 400);
  for (auto _ : state) {
    if (::write(fd, frame.data(), frame.size()) != static_cast<ssize_t>(frame.size())) {
      state.SkipWithError("write failed");
    }
  }
  ::close(fd);
  std::filesystem::remove(path);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * frame.size()));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_RawWriteRgbdFrameBaseline)->Unit(benchmark::kMillisecond)->UseRealTime();

// Reads a 40-frame recording (zstd) front to back; Arg 1 = CRCs checked, 0 = not.
void BM_McapReadRgbd(benchmark::State& state) {
  const std::string path = bench_path("read.mcap");
  std::uint64_t payload = 0;
  {
    mcap::McapWriter w(path);
    const auto c_rgb = ros_msgs::add_channel<ros_msgs::Image>(w, "/rgb");
    const auto c_depth = ros_msgs::add_channel<ros_msgs::Image>(w, "/depth");
    std::vector<std::uint8_t> buf;
    for (int f = 0; f < 40; ++f) {
      ros_msgs::write_message(w, c_rgb, f * 50'000'000ull, make_rgb(f), buf);
      payload += buf.size();
      ros_msgs::write_message(w, c_depth, f * 50'000'000ull, make_depth(f), buf);
      payload += buf.size();
    }
    w.close();
  }
  mcap::McapReaderOptions options;
  options.verify_crcs = state.range(0) != 0;
  for (auto _ : state) {
    mcap::McapReader r(path, options);
    mcap::MessageView m;
    std::size_t n = 0;
    while (r.next(m)) n += m.data.size();
    benchmark::DoNotOptimize(n);
    if (!r.issues().empty()) state.SkipWithError(r.issues().front().message.c_str());
  }
  std::filesystem::remove(path);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * payload));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * 40));
}
BENCHMARK(BM_McapReadRgbd)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

// Baseline: read(2) of the same uncompressed byte count from a page-cached file.
void BM_RawReadRgbdBaseline(benchmark::State& state) {
  const std::string path = bench_path("raw_read.bin");
  const std::size_t frame = make_rgb(0).data.size() + make_depth(0).data.size();
  std::vector<std::uint8_t> bytes(frame * 40, 7), back(bytes.size());
  {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (::write(fd, bytes.data(), bytes.size()) != static_cast<ssize_t>(bytes.size())) {
      state.SkipWithError("write failed");
    }
    ::close(fd);
  }
  for (auto _ : state) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    std::size_t got = 0;
    while (got < back.size()) {
      const ssize_t k = ::read(fd, back.data() + got, back.size() - got);
      if (k <= 0) break;
      got += static_cast<std::size_t>(k);
    }
    ::close(fd);
    benchmark::DoNotOptimize(back.data());
  }
  std::filesystem::remove(path);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * 40));
}
BENCHMARK(BM_RawReadRgbdBaseline)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
