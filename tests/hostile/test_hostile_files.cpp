// Hostile files other than recordings: PLY headers and values, a map too large for the
// rasterizer, a huge YAML, IMU CSVs with gaps and NaN, depth with no valid pixel, a serial IMU
// sample that is not finite.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>

#include "core/types/image.hpp"
#include "drivers/serial_imu/xsens_encoder.hpp"
#include "drivers/serial_imu/xsens_parser.hpp"
#include "io/image_io.hpp"
#include "mapping/ply_io.hpp"
#include "tests/hostile/hostile_util.hpp"

namespace vigs::hostile {
namespace {

const std::string kPlyProps =
    "property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float "
    "ny\nproperty float nz\nproperty float f_dc_0\nproperty float f_dc_1\nproperty float "
    "f_dc_2\nproperty float opacity\nproperty float scale_0\nproperty float scale_1\nproperty "
    "float scale_2\nproperty float rot_0\nproperty float rot_1\nproperty float rot_2\nproperty "
    "float rot_3\n";

std::string ply_message(const std::string& path) {
  try {
    (void)mapping::read_gaussian_ply(path);
  } catch (const mapping::PlyError& e) {
    return e.what();
  }
  return "";
}

TEST(HostilePly, VertexCountMustBeAWholeNumber) {
  TempDir dir;
  for (const char* count : {"abc", "-3", "12x", "1e3", ""}) {
    write_text(dir.file("bad.ply"), std::string("ply\nformat binary_little_endian 1.0\n") +
                                        "element vertex " + count + "\n" + kPlyProps +
                                        "end_header\n");
    const std::string what = ply_message(dir.file("bad.ply"));
    EXPECT_NE(what.find("bad.ply: header line 3: vertex count '"), std::string::npos)
        << count << ": " << what;
  }
}

TEST(HostilePly, NonFiniteValueIsAnErrorNamingVertexAndProperty) {
  TempDir dir;
  mapping::GaussianMap map;
  map.resize(3);
  for (std::size_t i = 0; i < 3; ++i) map.quat_wxyz[4 * i] = 1.0f;
  // The writer leaves a non-finite Gaussian out, so the NaN goes into a written file's bytes:
  // vertex 2's scale_1 (17 floats per vertex, scale_1 the twelfth).
  ASSERT_EQ(mapping::write_gaussian_ply(dir.file("nan.ply"), map), 0u);
  std::string bytes = read_text(dir.file("nan.ply"));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(bytes.data() + bytes.find("end_header\n") + 11 + (2 * 17 + 11) * sizeof(float), &nan,
              sizeof nan);
  write_text(dir.file("nan.ply"), bytes);
  const std::string what = ply_message(dir.file("nan.ply"));
  EXPECT_NE(what.find("nan.ply: vertex 2 property 'scale_1' is not finite"), std::string::npos)
      << what;
}

TEST(HostileRender, TooManyGaussianTilePairsIsAClearErrorNotASegfault) {
  // 600,000 Gaussians, each covering all 64 x 64 tiles of a 1024 x 1024 view: 2.5e9 pairs, more
  // than an int holds (the SIGSEGV / vector::_M_default_append).
  TempDir dir;
  mapping::GaussianMap map;
  const std::size_t n = 600'000;
  map.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    map.mean_w[3 * i + 2] = 2.0f + 1e-6f * static_cast<float>(i);
    for (int k = 0; k < 3; ++k) map.log_scale[3 * i + k] = std::log(5.0f);
    map.quat_wxyz[4 * i] = 1.0f;
    map.opacity_logit[i] = 0.0f;
  }
  mapping::write_gaussian_ply(dir.file("big.ply"), map);
  write_text(dir.file("cam.yaml"),
             "camera:\n  width_px: 1024\n  height_px: 1024\n  fx_px: 500\n  fy_px: 500\n"
             "  cx_px: 512\n  cy_px: 512\n");
  const VigsRun r =
      vigs(dir, "render --map " + dir.file("big.ply") + " --camera " + dir.file("cam.yaml") +
                    " --pose '0 0 0 0 0 0 1' --out " + dir.file("img.png"));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("rasterizer: more than 268435456 Gaussian-tile pairs"), std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("img.png")));
}

TEST(HostileYaml, MillionElementListIsAClearError) {
  TempDir dir;
  std::string text = "camera:\n  width_px: [";
  for (int i = 0; i < 1'000'000; ++i) text += i ? ",0" : "0";
  text += "]\n";
  write_text(dir.file("huge.yaml"), text);
  const VigsRun r = vigs(dir, "config check " + dir.file("huge.yaml"));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("huge.yaml"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("file is larger than 262144 bytes"), std::string::npos) << r.err;
}

TEST(HostileImuCsv, StampGapBeyondMaxGapIsAnErrorNotAnHourOfSleep) {
  TempDir dir;
  std::string csv = "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\n";
  for (int i = 0; i < 5; ++i) {
    const long long t = 1'000'000'000LL + i * 5'000'000LL + (i >= 3 ? 3'600'000'000'000LL : 0);
    csv += std::to_string(t) + ",0,0,0,0,0,9.81\n";
  }
  write_text(dir.file("gap.csv"), csv);
  const auto t0 = std::chrono::steady_clock::now();
  const VigsRun r = vigs(dir, "imu play " + dir.file("gap.csv") + " --delay 0");
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(30));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("gap.csv:5: stamp gap of 3600.005000 s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("exceeds --max-gap 1 s"), std::string::npos) << r.err;
}

TEST(HostileImuCsv, NanValueIsAnErrorNamingTheLine) {
  TempDir dir;
  write_text(dir.file("nan.csv"),
             "1000000000,0,0,0,0,0,9.81\n1005000000,nan,0,0,0,0,9.81\n1010000000,0,0,0,0,0,9.81\n");
  const VigsRun r = vigs(dir, "imu play " + dir.file("nan.csv") + " --delay 0");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("nan.csv:2: value is not finite"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
}

TEST(HostileSerialImu, NonFiniteSampleIsDroppedAndCounted) {
  struct Collect final : drivers::ImuSampleSink {
    int samples = 0;
    void on_sample(const drivers::DeviceImuSample& s) noexcept override {
      for (int k = 0; k < 3; ++k) EXPECT_TRUE(std::isfinite(s.accel_mps2[k]));
      ++samples;
    }
  } sink;
  drivers::XsensMtParser parser;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<std::uint8_t> bytes;
  for (int i = 0; i < 4; ++i) {
    const auto msg = drivers::xsens::encode_mtdata2(
        static_cast<std::uint32_t>(100 * i), {i == 2 ? nan : 0.0, 0.0, 9.81}, {0.0, 0.0, 0.0});
    bytes.insert(bytes.end(), msg.begin(), msg.end());
  }
  parser.feed(bytes.data(), bytes.size(), sink);
  EXPECT_EQ(sink.samples, 3);
  EXPECT_EQ(parser.counters().non_finite_sample.get(), 1u);
  EXPECT_EQ(parser.counters().packets_ok.get(), 3u);
}

TEST(HostileMap, DepthWithNoValidPixelIsAnErrorNotAnEmptyMap) {
  TempDir dir;
  vigs::ImageU8 rgb(32, 24, 3);
  vigs::ImageU16 depth(32, 24, 1);  // all 0: invalid, as NaN / Inf / out-of-range depth becomes
  io::write_png(dir.file("c.png"), rgb);
  io::write_png_u16(dir.file("d.png"), depth);
  write_text(dir.file("cam.yaml"),
             "camera:\n  width_px: 32\n  height_px: 24\n  fx_px: 20\n  fy_px: 20\n  cx_px: 16\n"
             "  cy_px: 12\n");
  write_text(dir.file("frames.txt"), "0 c.png d.png 0 0 0 0 0 0 1\n");
  const VigsRun r =
      vigs(dir, "map --camera " + dir.file("cam.yaml") + " --frames " + dir.file("frames.txt") +
                    " --iterations 5 --quiet --out " + dir.file("map.ply"));
  EXPECT_EQ(r.status, 1) << r.err << r.out;
  EXPECT_NE(r.err.find("d.png: no depth pixel in"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("map.ply")));
}

}  // namespace
}  // namespace vigs::hostile
