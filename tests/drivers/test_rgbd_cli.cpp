// `vigs rgbd play FILE.oni` as a real process: one JSON line per frame with the clip's centre
// pixels and 1/30 s stamp steps, then the driver's counters; a missing file exits 1 naming it.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "../common/temp_files.hpp"
#include "io/oni/oni_clip_writer.hpp"
#include "tests/common/cli_process.hpp"

namespace vigs::drivers {
namespace {

// Removed when the test program exits, passed or failed.
std::string temp_path(const std::string& name) {
  static vigs::test::TempFiles files("rgbd_cli");
  return files.path(name);
}

using test_cli::run_output;

TEST(RgbdCli, PlaysAClipFrameByFrameThenPrintsCounters) {
  constexpr std::uint32_t w = 32, h = 24;
  constexpr int kFrames = 6;
  const std::string clip = temp_path("clip.oni");
  {
    io::oni::OniClipWriter writer(clip, {w, h, 30});
    std::vector<std::uint16_t> depth(w * h);
    std::vector<std::uint8_t> rgb(w * h * 3);
    for (int f = 0; f < kFrames; ++f) {
      for (auto& d : depth) d = static_cast<std::uint16_t>(1000 + 10 * f);
      for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<std::uint8_t>(i % 3 + f);
      writer.add_frame(depth, rgb);
    }
    writer.close();
  }
  const auto [out, status] =
      run_output(std::string(VIGS_BIN) + " rgbd play " + clip + " --width 32 --height 24 --ring 8");
  ASSERT_EQ(status, 0) << out;
  std::istringstream lines(out);
  std::string line;
  int frames = 0;
  const std::regex frame_re(
      R"(\{"sequence": (\d+), "t_ns": \d+, "dt_ms": ([0-9.]+), "centre_depth_mm": (\d+), "centre_rgb": \[(\d+), (\d+), (\d+)\]\})");
  std::string last;
  while (std::getline(lines, line)) {
    std::smatch m;
    if (!std::regex_match(line, m, frame_re)) {
      last = line;
      continue;
    }
    EXPECT_EQ(std::stoi(m[1]), frames);
    if (frames > 0) {
      EXPECT_NEAR(std::stod(m[2]), 33.333, 0.002) << line;
    }
    EXPECT_EQ(std::stoi(m[3]), 1000 + 10 * frames);
    EXPECT_EQ(std::stoi(m[4]), frames);  // R G B = 0 1 2 (+ frame)
    EXPECT_EQ(std::stoi(m[6]), 2 + frames);
    ++frames;
  }
  EXPECT_EQ(frames, kFrames);
  EXPECT_NE(last.find("\"delivered\": 6"), std::string::npos) << last;
  EXPECT_NE(last.find("\"dropped_ring_full\": 0"), std::string::npos) << last;
  EXPECT_NE(last.find("\"end_of_stream\": true"), std::string::npos) << last;
}

TEST(RgbdCli, TruncatedClipExitsOneNamingItInsteadOfHanging) {
  constexpr std::uint32_t w = 32, h = 24;
  const std::string clip = temp_path("half.oni");
  {
    io::oni::OniClipWriter writer(clip, {w, h, 30});
    std::vector<std::uint16_t> depth(w * h, 1000);
    std::vector<std::uint8_t> rgb(w * h * 3, 7);
    for (int f = 0; f < 20; ++f) writer.add_frame(depth, rgb);
    writer.close();
  }
  struct stat st {};
  ASSERT_EQ(::stat(clip.c_str(), &st), 0);
  ASSERT_EQ(::truncate(clip.c_str(), st.st_size / 2), 0);
  // `timeout` turns a hang into exit 124 instead of a stuck test.
  const auto [out, status] = run_output("timeout 30 " + std::string(VIGS_BIN) + " rgbd play " +
                                        clip + " --width 32 --height 24 --frame-timeout-ms 500");
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find(clip + "': playback made no progress"), std::string::npos) << out;
  EXPECT_NE(out.find("\"fault\": \"frame timeout\""), std::string::npos) << out;
  EXPECT_NE(out.find("\"sequence\": 0"), std::string::npos) << out;  // frames before the cut
}

TEST(RgbdCli, MissingFileExitsOneNamingIt) {
  const std::string clip = temp_path("missing.oni");
  const auto [out, status] = run_output(std::string(VIGS_BIN) + " rgbd play " + clip);
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find(clip), std::string::npos) << out;
}

}  // namespace
}  // namespace vigs::drivers
