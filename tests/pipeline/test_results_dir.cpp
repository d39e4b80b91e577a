#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "../common/temp_files.hpp"
#include "pipeline/results_dir.hpp"

namespace vigs::pipeline {
namespace {

TEST(RunStats, ReadsKnownNumbersAndIgnoresOtherKeys) {
  const RunStats st = parse_run_stats(
      R"({"producer": "x \"q\"", "frames": 41, "wall_s": 2.5, "nested": {"a": [1, {"b": "}"}]},
          "fps": null, "peak_rss_bytes": 1.5e8, "ok": true})",
      "stats.json");
  ASSERT_TRUE(st.frames && st.wall_s && st.peak_rss_bytes);
  EXPECT_EQ(*st.frames, 41.0);
  EXPECT_EQ(*st.wall_s, 2.5);
  EXPECT_EQ(*st.peak_rss_bytes, 1.5e8);
  EXPECT_FALSE(st.fps);  // null: not measured
  EXPECT_FALSE(st.gaussians);
  EXPECT_FALSE(parse_run_stats("{}", "s").frames);
  EXPECT_FALSE(parse_run_stats("{}", "s").map_poses);  // older results: the estimate
  EXPECT_EQ(parse_run_stats(R"({"map_poses": "ground_truth"})", "s").map_poses, "ground_truth");
  EXPECT_EQ(parse_run_stats(R"({"map_poses": "estimate"})", "s").map_poses, "estimate");
}

TEST(RunStats, MalformedInputNamesFileAndOffsetOrKey) {
  const auto msg = [](const std::string& text) {
    try {
      parse_run_stats(text, "run/stats.json");
    } catch (const ResultsFileError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(msg(R"({"frames": 4,})"), "run/stats.json: byte 13: expected '\"'");
  EXPECT_EQ(msg(R"({"fps": "fast"})"), "run/stats.json: key \"fps\" must be a number or null");
  EXPECT_EQ(msg(R"({"fps": -1})"), "run/stats.json: key \"fps\" must not be negative");
  EXPECT_EQ(msg(R"({"map_poses": "truth"})"),
            "run/stats.json: key \"map_poses\" must be \"estimate\" or \"ground_truth\"");
  EXPECT_EQ(msg(R"({"map_poses": 1})"),
            "run/stats.json: key \"map_poses\" must be \"estimate\" or \"ground_truth\"");
  EXPECT_EQ(msg(R"({"a": 1} x)"), "run/stats.json: byte 9: trailing text after the object");
  EXPECT_EQ(msg(R"({"a": [1, 2)"), "run/stats.json: byte 11: unterminated object or array");
  EXPECT_EQ(msg(""), "run/stats.json: byte 0: expected '{'");
}

TEST(Keyframes, RoundTripAndLineErrors) {
  vigs::test::TempFiles files("vigs_kf");  // removed also when an assertion ends the test
  const std::string path = files.path("keyframes.txt");
  const std::vector<double> t = {0.1, 0.30000000000000004, 1.25};
  {
    std::ofstream out(path);
    out << format_keyframe_times({1.25, 0.1, 0.30000000000000004}) << "\n  # c\n";
  }
  EXPECT_EQ(read_keyframe_times(path), t);  // sorted, bit-identical
  {
    std::ofstream out(path);
    out << "0.5 extra columns ignored\n0.7x\n";
  }
  try {
    read_keyframe_times(path);
    FAIL();
  } catch (const ResultsFileError& e) {
    EXPECT_EQ(std::string(e.what()), path + ":2: '0.7x' is not a timestamp in seconds");
  }
  std::filesystem::remove(path);
  EXPECT_THROW(read_keyframe_times(path), ResultsFileError);
}

}  // namespace
}  // namespace vigs::pipeline
