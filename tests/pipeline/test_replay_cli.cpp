// `vigs replay` end to end: a RESULTS_DIR that the eval readers parse and `vigs eval run`
// reports on, and damaged recordings refused with the file named.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/json_text.hpp"
#include "io/tum_trajectory.hpp"
#include "mapping/ply_io.hpp"
#include "pipeline/lockstep_replay.hpp"
#include "pipeline/recorded_motion.hpp"
#include "pipeline/results_dir.hpp"
#include "tests/common/cli_process.hpp"
#include "tests/pipeline/sim_sequence.hpp"

namespace vigs::pipeline {
namespace {

using testing::TempDir;

using test_cli::read_text;
using test_cli::run_status;

class ReplayCli : public ::testing::Test {
 protected:
  void SetUp() override {
    cfg_ = testing::small_office(3.0);
    path_ = dir_.file("office.mcap");
    testing::simulate(cfg_, path_);
    // The same settings for the binary (stride 2, as the library tests use).
    std::ofstream(dir_.file("robot.yaml")) << "tracking:\n  pixel_stride: 2\n";
  }
  std::string vigs(const std::string& args, const std::string& log) {
    return std::string(VIGS_BIN) + " " + args + " > " + dir_.file(log + ".out") + " 2> " +
           dir_.file(log + ".err");
  }
  /// Runs `vigs ARGS` with its output in LOG.out / LOG.err: success on exit code 0, else a
  /// failure carrying LOG.err.
  ::testing::AssertionResult vigs_ok(const std::string& args, const std::string& log) {
    const int status = run_status(vigs(args, log));
    if (status == 0) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "vigs " << args << ": exit " << status << "\n"
                                         << read_text(dir_.file(log + ".err"));
  }

  TempDir dir_;
  config::RobotConfig cfg_;
  std::string path_;
};

TEST_F(ReplayCli, WritesAResultsDirThatEvalReads) {
  const std::string out = dir_.file("results");
  ASSERT_TRUE(vigs_ok("replay " + path_ + " --out " + out + " --config " + dir_.file("robot.yaml") +
                          " --guess imu --quiet",
                      "replay"));

  const auto poses = io::read_tum_trajectory(out + "/" + pipeline::kTrajectoryFile);
  ASSERT_EQ(poses.size(), 61u);  // 3 s at 20 Hz, both ends
  EXPECT_DOUBLE_EQ(poses.front().t_s, 0.0);
  EXPECT_NEAR(poses.back().t_s, 3.0, 1e-9);

  const pipeline::RunStats stats = pipeline::read_run_stats(out + "/" + pipeline::kStatsFile);
  ASSERT_TRUE(stats.frames && stats.wall_s && stats.fps && stats.peak_rss_bytes);
  EXPECT_EQ(*stats.frames, 61.0);
  EXPECT_GT(*stats.wall_s, 0.0);
  EXPECT_NEAR(*stats.fps, *stats.frames / *stats.wall_s, 1e-6 * *stats.fps);
  EXPECT_GT(*stats.peak_rss_bytes, 1e6);
  const std::string stats_text = read_text(out + "/" + pipeline::kStatsFile);
  EXPECT_NE(stats_text.find("\"tracked\": 60"), std::string::npos) << stats_text;
  EXPECT_NE(stats_text.find("\"lost\": 0"), std::string::npos) << stats_text;
  EXPECT_NE(stats_text.find("\"guess\": \"imu\""), std::string::npos) << stats_text;

  const std::vector<double> kf =
      pipeline::read_keyframe_times(out + "/" + pipeline::kKeyframesFile);
  ASSERT_FALSE(kf.empty());
  EXPECT_DOUBLE_EQ(kf.front(), 0.0);  // the first frame starts the map
  for (const double t : kf) {
    bool found = false;
    for (const auto& p : poses) found = found || p.t_s == t;
    EXPECT_TRUE(found) << "keyframe stamp " << t << " is not a trajectory stamp";
  }
  // No temporary file left behind by the atomic writes.
  for (const auto& e : std::filesystem::directory_iterator(out))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();

  ASSERT_TRUE(vigs_ok("eval run " + out + " --gt " + path_ + " --no-plots --no-render", "eval"));
  const std::string report = read_text(dir_.file("eval.out"));
  EXPECT_NE(report.find("\"pairs\": 61"), std::string::npos) << report;
  EXPECT_TRUE(std::filesystem::exists(out + "/report.md"));
}

TEST_F(ReplayCli, FramesOptionLimitsTheReplay) {
  const std::string out = dir_.file("first10");
  ASSERT_TRUE(vigs_ok("replay " + path_ + " --out " + out +
                          " --frames 10 --guess previous_pose "
                          "--quiet",
                      "frames"));
  EXPECT_EQ(io::read_tum_trajectory(out + "/" + pipeline::kTrajectoryFile).size(), 10u);
  EXPECT_EQ(*pipeline::read_run_stats(out + "/" + pipeline::kStatsFile).frames, 10.0);
}

TEST_F(ReplayCli, SkipFramesStartsLate) {
  const std::string out = dir_.file("late");
  ASSERT_TRUE(vigs_ok("replay " + path_ + " --out " + out + " --config " + dir_.file("robot.yaml") +
                          " --skip-frames 5 --quiet",
                      "late"));
  const auto poses = io::read_tum_trajectory(out + "/" + pipeline::kTrajectoryFile);
  ASSERT_EQ(poses.size(), 56u);  // 61 frames, the first 5 not tracked
  EXPECT_NEAR(poses.front().t_s, 0.25, 1e-9);
  const std::string stats_text = read_text(out + "/" + pipeline::kStatsFile);
  EXPECT_NE(stats_text.find("\"frames_skipped_at_start\": 5"), std::string::npos) << stats_text;
}

TEST_F(ReplayCli, MapIterationsWriteAMapThatEvalRenders) {
  const std::string out = dir_.file("mapped");
  ASSERT_TRUE(vigs_ok("replay " + path_ + " --out " + out + " --config " + dir_.file("robot.yaml") +
                          " --map-iterations 2 --quiet",
                      "map"));
  ASSERT_TRUE(std::filesystem::exists(out + "/" + pipeline::kMapFile));
  const pipeline::RunStats stats = pipeline::read_run_stats(out + "/" + pipeline::kStatsFile);
  ASSERT_TRUE(stats.gaussians.has_value());
  EXPECT_GT(*stats.gaussians, 1000.0);
  EXPECT_NE(read_text(out + "/" + pipeline::kStatsFile).find("\"map_iterations\": 122"),
            std::string::npos);  // 2 after each of the 61 frames

  ASSERT_TRUE(vigs_ok("eval run " + out + " --gt " + path_ + " --no-plots", "map_eval"));
  const std::string report = read_text(dir_.file("map_eval.out"));
  const auto number_after = [&report](const std::string& key) {
    const std::size_t at = report.find("\"" + key + "\": ");
    return at == std::string::npos ? -1.0
                                   : std::strtod(report.c_str() + at + key.size() + 4, nullptr);
  };
  // A rendered map of what the camera saw (measured 16.8 dB, 23.1 dB where depth is valid); an
  // empty or misplaced map scores far lower.
  EXPECT_GT(number_after("psnr_db"), 14.0) << report;
  EXPECT_GT(number_after("psnr_valid_depth_db"), 20.0) << report;
}

// --map-poses ground_truth: the mapper alone, without tracking error. From the gravity start
// the estimate's world has the first camera at its origin, the ground truth's has it where
// the simulator put it, so the two maps lie apart by that offset; each renders well only at
// the poses it was built at, which `vigs eval run` takes from stats.json map_poses.
TEST_F(ReplayCli, MapPosesGroundTruthBuildsTheMapInTheGroundTruthsWorld) {
  const auto replay = [&](const std::string& name, const std::string& map_poses) {
    const std::string out = dir_.file(name);
    EXPECT_TRUE(vigs_ok("replay " + path_ + " --out " + out + " --config " +
                            dir_.file("robot.yaml") + " --frames 30 --map-iterations 2" +
                            " --initial-pose gravity --map-poses " + map_poses + " --quiet",
                        name));
    EXPECT_TRUE(vigs_ok("eval run " + out + " --gt " + path_ + " --no-plots", name + "_eval"));
    return io::Json::parse(read_text(dir_.file(name + "_eval.out")));
  };
  const io::Json at_truth = replay("at_truth", "ground_truth");
  const io::Json at_estimate = replay("at_estimate", "estimate");
  for (const auto& [js, poses] :
       {std::pair{&at_truth, "ground_truth"}, std::pair{&at_estimate, "estimate"}}) {
    ASSERT_TRUE((*js)["quality"].is_object()) << js->dump();
    EXPECT_EQ((*js)["quality"]["render_poses"], poses);
    // each map rendered where it was built: a map of what the camera saw (about 23 dB over
    // valid depth, MapIterationsWriteAMapThatEvalRenders); rendered 1 m off it is far lower
    EXPECT_GT((*js)["quality"]["every_nth"]["psnr_valid_depth_db"].get<double>(), 20.0)
        << js->dump();
  }
  // Both render the frames the 30-frame run processed, not the 3 s the ground truth covers.
  for (const char* set : {"every_nth", "held_out"}) {
    EXPECT_EQ(at_truth["quality"][set]["frames"], at_estimate["quality"][set]["frames"]) << set;
    EXPECT_GT(at_estimate["quality"][set]["frames"].get<int>(), 0) << set;
  }
  EXPECT_NE(read_text(dir_.file("at_truth") + "/" + pipeline::kStatsFile)
                .find("\"map_poses\": \"ground_truth\""),
            std::string::npos);
  // The two maps lie apart by the ground truth's start offset (the recording's first pose).
  const auto centroid = [&](const std::string& name) {
    const mapping::GaussianMap map =
        mapping::read_gaussian_ply(dir_.file(name) + "/" + pipeline::kMapFile);
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < map.size(); ++i)
      c += Eigen::Vector3d(map.mean_w[3 * i], map.mean_w[3 * i + 1], map.mean_w[3 * i + 2]);
    return Eigen::Vector3d(c / static_cast<double>(std::max<std::size_t>(map.size(), 1)));
  };
  const RecordedMotion motion = read_recorded_motion(path_);
  ASSERT_FALSE(motion.body_poses.empty());
  const double start_offset_m = motion.body_poses.front().T_w_x.translation().norm();
  ASSERT_GT(start_offset_m, 1.0) << "the simulator's start is at the origin: no test";
  EXPECT_GT((centroid("at_truth") - centroid("at_estimate")).norm(), 0.5 * start_offset_m);
}

TEST_F(ReplayCli, MapBudgetBuildsAMapWithTheBudgetInItsStats) {
  const std::string out = dir_.file("budget");
  ASSERT_TRUE(vigs_ok("replay " + path_ + " --out " + out + " --config " + dir_.file("robot.yaml") +
                          " --frames 20 --map-budget-ms 15 --quiet",
                      "budget"));
  ASSERT_TRUE(std::filesystem::exists(out + "/" + pipeline::kMapFile));
  const std::string stats = read_text(out + "/" + pipeline::kStatsFile);
  EXPECT_NE(stats.find("\"map_budget_ms\": 15"), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"map_budget_overruns\": "), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"map_bytes_per_gaussian\": "), std::string::npos) << stats;
  // the mapper's memory by owner, its total beside the process's peak RSS
  const io::Json js = io::Json::parse(stats);
  ASSERT_TRUE(js.contains("map_memory_bytes")) << stats;
  ASSERT_TRUE(js.contains("map_memory_by_owner_bytes")) << stats;
  const io::Json& owners = js["map_memory_by_owner_bytes"];
  std::uint64_t sum = 0;
  for (const auto& [owner, bytes] : owners.items()) sum += bytes.get<std::uint64_t>();
  EXPECT_EQ(owners.size(), 8u) << stats;
  EXPECT_EQ(js["map_memory_bytes"].get<std::uint64_t>(), sum) << stats;
  const std::uint64_t gaussians = js["gaussians"].get<std::uint64_t>();
  ASSERT_GT(gaussians, 0u) << stats;
  EXPECT_GE(owners["map_params"].get<std::uint64_t>(), 14 * sizeof(float) * gaussians) << stats;
  // two moments per parameter: the first as bfloat16, the second as float (mapping/adam.hpp)
  EXPECT_GE(owners["adam_moments"].get<std::uint64_t>(),
            14 * (sizeof(std::uint16_t) + sizeof(float)) * gaussians)
      << stats;
  EXPECT_GT(owners["keyframes"].get<std::uint64_t>(), 0u) << stats;
  EXPECT_GT(owners["occupancy"].get<std::uint64_t>(), 0u) << stats;
  EXPECT_LT(js["map_memory_bytes"].get<double>(), js["peak_rss_bytes"].get<double>()) << stats;
  EXPECT_NE(stats.find("\"map_gated_points\": "), std::string::npos) << stats;
  // how many iterations fit follows the wall clock (a loaded machine may fit none), so only
  // the key is checked
  EXPECT_NE(stats.find("\"map_iterations\": "), std::string::npos) << stats;
}

TEST_F(ReplayCli, DamagedRecordingsAreRefusedNamingTheFile) {
  const std::string bytes = read_text(path_);
  ASSERT_GT(bytes.size(), 100000u);
  const std::string truncated = dir_.file("truncated.mcap");
  std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  std::string flipped_bytes = bytes;
  flipped_bytes[bytes.size() / 3] = static_cast<char>(flipped_bytes[bytes.size() / 3] ^ 0x5a);
  const std::string flipped = dir_.file("flipped.mcap");
  std::ofstream(flipped, std::ios::binary) << flipped_bytes;
  const std::string not_mcap = dir_.file("robot.yaml");
  const std::string missing = dir_.file("missing.mcap");

  for (const std::string& bad : {truncated, flipped, not_mcap, missing}) {
    SCOPED_TRACE(bad);
    // The library throws RecordingError naming the file...
    try {
      replay_recording(bad, cfg_, {});
      ADD_FAILURE() << "no error";
    } catch (const RecordingError& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
    // ... and the command exits 1 with that message, writing nothing.
    const std::string out = dir_.file("bad_results");
    EXPECT_EQ(run_status(vigs("replay " + bad + " --out " + out + " --quiet", "bad")), 1);
    const std::string err = read_text(dir_.file("bad.err"));
    EXPECT_NE(err.find(bad), std::string::npos) << err;
    EXPECT_FALSE(std::filesystem::exists(out + "/" + pipeline::kTrajectoryFile));
  }
}

TEST(ReplayWithoutImu, ImuGuessIsRefusedAndTheBaselinesStartAtIdentity) {
  // Frames only: no IMU, no ground truth.
  TempDir dir;
  const config::RobotConfig cfg = testing::small_office(1.0);
  const std::string path = dir.file("frames_only.mcap");
  {
    sim::Simulator simulator(cfg);
    sim::McapSinkOptions opt;
    sim::McapSink sink(path, opt);
    sim::RgbdFrame frame;
    for (std::uint64_t i = 0; i < 5; ++i) {
      const double t_s = 0.05 * static_cast<double>(i);
      simulator.render_at(t_s, i, frame);
      sink.frame(static_cast<std::int64_t>(i) * 50'000'000, simulator.camera(), frame);
    }
    sink.close();
  }
  ReplayOptions opt;
  opt.guess = tracking::InitialGuessMode::imu;
  try {
    replay_recording(path, cfg, opt);
    ADD_FAILURE() << "imu guess without IMU samples was accepted";
  } catch (const RecordingError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("no sensor_msgs/Imu"), std::string::npos) << e.what();
  }
  opt.guess = tracking::InitialGuessMode::previous_pose;
  const ReplayResult r = replay_recording(path, cfg, opt);
  EXPECT_EQ(r.frames.size(), 5u);
  EXPECT_EQ(r.initial_pose, InitialPoseSource::identity);
  EXPECT_TRUE(r.frames.front().T_w_c.isApprox(geometry::Pose::Identity()));
  EXPECT_EQ(r.counters.tracked, 4);  // the camera is at rest: every frame registers
}

}  // namespace
}  // namespace vigs::pipeline
