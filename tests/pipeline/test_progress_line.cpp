// `vigs run`'s progress line (src/pipeline/progress_line.hpp, issue #14 item 6): a replay gets
// an ETA from the frames still to play at the rate played so far; a live source shows "live".
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "pipeline/progress_line.hpp"

namespace vigs::pipeline {
namespace {

TEST(ProgressEta, FramesLeftOverTheWallRateSoFar) {
  // 40 of 200 frames in 2 s: 20 frames/s, 160 left -> 8 s.
  const std::optional<double> eta_s = progress_eta_s(40, 200, 2.0);
  ASSERT_TRUE(eta_s);
  EXPECT_DOUBLE_EQ(*eta_s, 8.0);
  // Half the rate (a real-time factor of 0.5 on a 20 Hz recording): twice the time.
  EXPECT_DOUBLE_EQ(*progress_eta_s(40, 200, 4.0), 16.0);
}

TEST(ProgressEta, ZeroAtTheEnd) {
  EXPECT_DOUBLE_EQ(*progress_eta_s(200, 200, 10.0), 0.0);
  EXPECT_DOUBLE_EQ(*progress_eta_s(201, 200, 10.0), 0.0);  // never negative
}

TEST(ProgressEta, NoneWithoutAnEndOrARate) {
  EXPECT_FALSE(progress_eta_s(40, 0, 2.0));   // live: no end
  EXPECT_FALSE(progress_eta_s(0, 200, 2.0));  // nothing played yet
  EXPECT_FALSE(progress_eta_s(40, 200, 0.0));
  EXPECT_FALSE(progress_eta_s(40, 200, std::numeric_limits<double>::quiet_NaN()));
}

TEST(ProgressEta, DurationText) {
  EXPECT_EQ(format_duration_hms(0.0), "0:00");
  EXPECT_EQ(format_duration_hms(8.4), "0:08");
  EXPECT_EQ(format_duration_hms(65.0), "1:05");
  EXPECT_EQ(format_duration_hms(3723.0), "1:02:03");
  EXPECT_EQ(format_duration_hms(-3.0), "0:00");
  EXPECT_EQ(format_duration_hms(std::numeric_limits<double>::infinity()), "0:00");
}

LiveProgress sample() {
  LiveProgress p;
  p.frames = 38;
  p.frames_played = 40;  // two dropped: the ETA follows the source, not the tracker
  p.elapsed_s = 2.0;
  p.stream_s = 1.9;
  p.track_p50_ns = 3'100'000;
  p.track_p99_ns = 5'200'000;
  p.drops = 2;
  p.gaussians = 1200;
  return p;
}

TEST(ProgressLine, ReplayShowsFramesOfTotalAndEta) {
  LiveProgress p = sample();
  p.frames_total = 200;
  EXPECT_EQ(format_progress_line(p),
            "frames    38/200  rtf 0.95  tracker p50 3.1 / p99 5.2 ms  drops 2  "
            "gaussians 1200  ETA 0:08");
}

TEST(ProgressLine, ReplayBeforeAnyFrameHasNoEtaYet) {
  LiveProgress p;
  p.frames_total = 200;
  const std::string line = format_progress_line(p);
  EXPECT_NE(line.find("ETA --:--"), std::string::npos) << line;
}

TEST(ProgressLine, LiveShowsNoEta) {
  const std::string line = format_progress_line(sample());  // frames_total 0: live
  EXPECT_EQ(line,
            "frames    38  rtf 0.95  tracker p50 3.1 / p99 5.2 ms  drops 2  gaussians 1200  live");
  EXPECT_EQ(line.find("ETA"), std::string::npos) << line;
}

}  // namespace
}  // namespace vigs::pipeline
