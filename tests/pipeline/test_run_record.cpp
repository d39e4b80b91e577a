// `vigs run --record F.mcap` (pipeline/live_pipeline.hpp, src/record): a short simulated office
// sequence (240x160, 5 s) played through the REAL drivers in real time -- an .oni clip through
// OpenNI2, Xsens bytes on a pseudo-terminal through the serial driver -- while the recorder
// thread writes the drivers' taps and the tracker's poses into an MCAP file. Then:
//  - replaying that file in lockstep as the run did (`vigs replay --as-run`: the frames it
//    tracked, every IMU sample) gives bit for bit the trajectory of the run that recorded it;
//  - its /vigs/pose topic holds that same trajectory; the official MCAP readers open it;
//  - `vigs run --record` killed with SIGKILL leaves F.mcap.partial, which `vigs replay` refuses
//    and `vigs replay --allow-truncated` replays up to the last chunk, saying so;
//  - an output that is an input, or --record with --lockstep, is refused before anything runs.
// DDS domain 191 (loopback), shared-memory segments cleaned up.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "../common/cli_process.hpp"
#include "../dds/shm_janitor.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/typed_io.hpp"
#include "pipeline/live_pipeline.hpp"
#include "sim_sequence.hpp"

namespace vigs::pipeline {
namespace {

constexpr double kSeconds = 5.0;
using test_cli::run_output;

class RunRecord : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir();
    testing::simulate(testing::live_test_config(kSeconds), dir_->file("office.mcap"));
    // The same settings for the `vigs run` / `vigs replay` processes.
    std::ofstream(dir_->file("small.yaml"))
        << "camera:\n  width_px: 240\n  height_px: 160\n  fx_px: 138.56406460551018\n"
           "  fy_px: 138.56406460551018\n  cx_px: 120.0\n  cy_px: 80.0\n"
           "tracking:\n  pixel_stride: 2\n"
           "mapping:\n  threads: 1\n"
           "rt:\n  lock_memory: false\n  realtime_priorities: false\n  pin_cpus: false\n"
           "dds:\n  qos_profiles: "
        << VIGS_SOURCE_DIR << "/firmware_config/dds/qos_profiles.xml\n";
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string file(const std::string& name) { return dir_->file(name); }
  static testing::TempDir* dir_;
};
testing::TempDir* RunRecord::dir_ = nullptr;

TEST_F(RunRecord, ReplayingTheRecordingGivesTheRunsTrajectoryBitForBit) {
  const config::RobotConfig cfg = testing::live_test_config(kSeconds);
  LiveOptions o;
  o.recording = file("office.mcap");
  o.through_drivers = true;
  // The tracker must see every frame for the two runs to match: no mapper competing for the
  // two cores (the mapper does not feed back into tracking).
  o.mapping = false;
  o.record_path = file("rec.mcap");
  const LiveResult r = run_live(cfg, o);
  const std::size_t n = r.replay.frames.size();
  ASSERT_GT(n, 60u);
  ASSERT_TRUE(r.record && r.camera_driver && r.imu_driver);
  EXPECT_TRUE(std::filesystem::exists(o.record_path));
  EXPECT_FALSE(std::filesystem::exists(o.record_path + ".partial"));

  // The recorder lost nothing and wrote every frame the driver delivered, every sample it
  // stamped, every byte it read and every pose.
  const LiveRecordResult& rec = *r.record;
  EXPECT_EQ(rec.tap_drops(), 0u);
  EXPECT_EQ(rec.written.frames, r.camera_driver->delivered);
  EXPECT_EQ(rec.written.imu_samples, r.imu_driver->samples_out);
  EXPECT_EQ(rec.written.serial_bytes, r.imu_driver->bytes_read);
  EXPECT_EQ(rec.written.poses, n);

  // Replayed in lockstep as the run did (`vigs replay --as-run`: only the frames it tracked,
  // i.e. with a pose on /vigs/pose; the tracker skips to the newest frame and releases those
  // before the IMU's first sample): the same poses, bit for bit, at the same stamps (the run's
  // result is in the source recording's clock; the new file is in the drivers' host clock).
  ReplayOptions as_run;
  as_run.as_run = true;
  const ReplayResult again = replay_recording(o.record_path, cfg, as_run);
  ASSERT_EQ(again.frames.size(), n);
  // The same IMU samples went in (a frame whose IMU came late, imu_late, had fewer: the replay
  // feeds it the samples the run had, from /vigs/pose/imu_used).
  EXPECT_EQ(again.imu_samples_fed, r.tracker.imu_samples);
  for (std::size_t i = 0; i < n; ++i) {
    const TrackedFrame& live = r.replay.frames[i];
    const TrackedFrame& replayed = again.frames[i];
    ASSERT_EQ(replayed.t_ns, live.t_ns + r.host_minus_recording_ns) << i;
    ASSERT_TRUE(replayed.T_w_c.matrix() == live.T_w_c.matrix())
        << "frame " << i << "\nlive\n"
        << live.T_w_c.matrix() << "\nreplayed\n"
        << replayed.T_w_c.matrix();
  }

  // The recorded poses are the run's trajectory (host stamps).
  io::mcap::McapReader reader(o.record_path);
  io::mcap::MessageView m;
  std::size_t poses = 0;
  while (reader.next(m)) {
    io::ros_msgs::PoseStamped p;
    if (m.channel->topic != record::kPoseTopic || !io::ros_msgs::decode_message(m, p)) continue;
    ASSERT_LT(poses, n);
    const TrackedFrame& live = r.replay.frames[poses];
    EXPECT_EQ(p.header.stamp.to_ns(), live.t_ns + r.host_minus_recording_ns);
    EXPECT_EQ(p.header.frame_id, cfg.dds.map_frame_id);
    EXPECT_EQ(p.pose.position.x, live.T_w_c.translation().x());
    EXPECT_EQ(p.pose.position.z, live.T_w_c.translation().z());
    ++poses;
  }
  EXPECT_TRUE(reader.issues().empty());
  EXPECT_EQ(poses, n);

  // The official TypeScript readers (indexed with CRCs, stream, ROS 2 decoders).
  if (std::system("command -v node >/dev/null 2>&1") != 0) GTEST_SKIP() << "node not installed";
  const auto [ts, ts_status] = run_output("node " + std::string(VIGS_SOURCE_DIR) +
                                          "/tests/conformance/summarize_mcap.mjs " + o.record_path);
  ASSERT_EQ(ts_status, 0) << ts;
  EXPECT_NE(ts.find(R"("/vigs/pose":{"schema":"geometry_msgs/msg/PoseStamped","messages":)" +
                    std::to_string(n) + ","),
            std::string::npos)
      << ts;
  EXPECT_NE(
      ts.find(R"("/vigs/pose/imu_used":{"schema":"sensor_msgs/msg/TimeReference","messages":)" +
              std::to_string(n) + ","),
      std::string::npos)
      << ts;
  EXPECT_NE(ts.find(R"("/vigs/rgb":{"schema":"sensor_msgs/msg/Image","messages":)" +
                    std::to_string(rec.written.frames) + ","),
            std::string::npos)
      << ts;
  EXPECT_NE(ts.find(R"("/vigs/imu":{"schema":"sensor_msgs/msg/Imu","messages":)" +
                    std::to_string(rec.written.imu_samples) + ","),
            std::string::npos)
      << ts;
}

TEST_F(RunRecord, SigkillLeavesAPartialFileReplayAcceptsWithAllowTruncated) {
  const dds::test::ShmJanitor janitor;
  const std::string rec = file("killed.mcap"), partial = rec + ".partial";
  const pid_t pid = ::fork();
  if (pid == 0) {
    const std::string log = file("killed.log");
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, 1);
    ::dup2(fd, 2);
    const std::string source = "replay:" + file("office.mcap"), cfg = file("small.yaml"),
                      out = file("killed_results");
    ::execl(VIGS_BIN, VIGS_BIN, "run", "--source", source.c_str(), "--through-drivers", "--config",
            cfg.c_str(), "--dds-domain", "191", "--record", rec.c_str(), "--quiet", "--out",
            out.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Two chunks (each closes after 1 s of log time) in the partial file, then SIGKILL.
  const auto t0 = std::chrono::steady_clock::now();
  std::error_code ec;
  while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(40)) {
    std::int64_t first = -1, last = -1;
    if (std::filesystem::exists(partial, ec)) {
      io::mcap::McapReader probe(partial);
      io::mcap::MessageView m;
      while (probe.next(m)) {
        if (first < 0) first = static_cast<std::int64_t>(m.log_time_ns);
        last = static_cast<std::int64_t>(m.log_time_ns);
      }
    }
    if (last - first > 1'500'000'000) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << test_cli::read_text(file("killed.log"));
  EXPECT_FALSE(std::filesystem::exists(rec));
  ASSERT_TRUE(std::filesystem::exists(partial));

  const std::string replay = std::string(VIGS_BIN) + " replay " + partial + " --config " +
                             file("small.yaml") + " --quiet --out ";
  const auto [refused, refused_status] = run_output(replay + file("res_refused"));
  EXPECT_EQ(refused_status, 1) << refused;
  EXPECT_NE(refused.find("--allow-truncated"), std::string::npos) << refused;
  const auto [allowed, allowed_status] =
      run_output(replay + file("res_prefix") + " --allow-truncated");
  ASSERT_EQ(allowed_status, 0) << allowed;
  EXPECT_NE(allowed.find("damaged recording (truncated"), std::string::npos) << allowed;
  const std::string trajectory = test_cli::read_text(file("res_prefix/trajectory.tum"));
  EXPECT_GE(std::count(trajectory.begin(), trajectory.end(), '\n'), 20) << trajectory;
}

TEST_F(RunRecord, RefusesAnInputAsItsOutputAndLockstep) {
  std::filesystem::create_directories(file("res_refused_run"));
  const std::string run = std::string(VIGS_BIN) + " run --source replay:" + file("office.mcap") +
                          " --config " + file("small.yaml") + " --dds-domain 192 --quiet --out " +
                          file("res_refused_run");
  const auto [same, same_status] =
      run_output(run + " --through-drivers --record " + file("office.mcap"));
  EXPECT_EQ(same_status, 1) << same;
  EXPECT_NE(same.find("refusing to overwrite an input"), std::string::npos) << same;
  const auto [config, config_status] =
      run_output(run + " --through-drivers --record " + file("small.yaml"));
  EXPECT_EQ(config_status, 1) << config;
  EXPECT_NE(config.find("refusing to overwrite an input"), std::string::npos) << config;
  const auto [inside, inside_status] =
      run_output(run + " --through-drivers --record " + file("res_refused_run/r.mcap"));
  EXPECT_EQ(inside_status, 1) << inside;
  EXPECT_NE(inside.find("is inside --out"), std::string::npos) << inside;
  const auto [lockstep, lockstep_status] =
      run_output(run + " --lockstep --record " + file("lockstep.mcap"));
  EXPECT_EQ(lockstep_status, 1) << lockstep;
  EXPECT_NE(lockstep.find("--record records the drivers in real time; --lockstep"),
            std::string::npos)
      << lockstep;
  const auto [rings, rings_status] = run_output(run + " --record " + file("rings.mcap"));
  EXPECT_EQ(rings_status, 1) << rings;
  EXPECT_NE(rings.find("add --through-drivers"), std::string::npos) << rings;
  for (const char* f : {"lockstep.mcap", "rings.mcap", "res_refused_run/r.mcap"})
    EXPECT_FALSE(std::filesystem::exists(file(f))) << f;
}

}  // namespace
}  // namespace vigs::pipeline
