// The live pipeline (src/pipeline/live_pipeline.hpp) on a short simulated office sequence
// (240x160): lockstep gives exactly `vigs replay`'s trajectory, twice; real time tracks every
// frame it keeps and counts what it skips; a subscriber in a second process (`vigs echo`)
// receives every published pose in order with the frames' stamps; a stop request drains.
// `vigs run`'s RESULTS_DIR (issue #14 item 7): SIGTERM saves it whole with its report; a reused
// folder keeps no earlier file; a second signal exits at once and leaves it whole or absent.
#include <gtest/gtest.h>

#include <signal.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../dds/process.hpp"
#include "../dds/shm_janitor.hpp"
#include "eval/trajectory_file.hpp"
#include "io/json_text.hpp"
#include "io/recording/recorded_frames.hpp"
#include "mapping/ply_io.hpp"
#include "pipeline/live_pipeline.hpp"
#include "pipeline/recording_source.hpp"
#include "sim_sequence.hpp"

namespace vigs::pipeline {
namespace {

config::RobotConfig live_config() {
  return testing::live_test_config(4.0);
}

class LivePipeline : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir();
    testing::simulate(live_config(), dir_->file("office.mcap"));
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::string recording() { return dir_->file("office.mcap"); }
  static testing::TempDir* dir_;
};
testing::TempDir* LivePipeline::dir_ = nullptr;

bool same_pose(const geometry::Pose& a, const geometry::Pose& b) {
  return a.matrix() == b.matrix();  // bit-identical, not approximately equal
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

/// Every file of a `vigs run` RESULTS_DIR is there and reads whole: trajectory.tum parses,
/// stats.json parses and counts its poses, map.ply reads (mapping on), report.md names the
/// folder itself (not the temporary one it was written in) when `report`.
void expect_whole_results(const std::string& out, bool map, bool report) {
  SCOPED_TRACE(out);
  const eval::Trajectory tum = eval::load_trajectory_file(out + "/trajectory.tum");
  EXPECT_GT(tum.poses.size(), 0u);
  const io::Json stats = io::Json::parse(read_text(out + "/stats.json"));
  EXPECT_EQ(stats.at("frames").get<std::size_t>(), tum.poses.size())
      << "stats.json frames and trajectory.tum poses differ";
  EXPECT_EQ(std::filesystem::exists(out + "/map.ply"), map);
  if (map) {
    EXPECT_NO_THROW(mapping::read_gaussian_ply(out + "/map.ply"));
  }
  EXPECT_EQ(std::filesystem::exists(out + "/report.md"), report);
  if (report && std::filesystem::exists(out + "/report.md")) {
    const std::string md = read_text(out + "/report.md");
    EXPECT_EQ(md.rfind("# VIGS evaluation report", 0), 0u) << md;
    EXPECT_NE(md.find("- results: `" + out + "`"), std::string::npos) << md;
    EXPECT_NE(md.find("## Not measured in this report"), std::string::npos) << md;
  }
}

/// No hidden ".NAME.tmp-*" staging folder is left beside RESULTS_DIR `out`.
void expect_no_staging_left(const std::string& out) {
  const std::filesystem::path p(out);
  const std::string prefix = "." + p.filename().string() + ".tmp-";
  for (const auto& e : std::filesystem::directory_iterator(p.parent_path()))
    EXPECT_NE(e.path().filename().string().rfind(prefix, 0), 0u) << e.path();
}

/// Sends `sig` to `pid`; a process already gone (or a zombie) is not an error here.
void signal_child(pid_t pid, int sig) {
  (void)::kill(pid, sig);
}

/// Waits (up to `timeout`) until `sig` is no longer pending for process `pid` (/proc ShdPnd):
/// its handler has taken it, so a second one is delivered on its own, not merged into it.
bool wait_signal_taken(pid_t pid, int sig, std::chrono::milliseconds timeout) {
  const auto give_up = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    std::string line;
    bool pending = false;
    while (std::getline(status, line))
      if (line.rfind("ShdPnd:", 0) == 0)
        pending = (std::stoull(line.substr(7), nullptr, 16) >> (sig - 1)) & 1u;
    if (!pending) return true;
    if (std::chrono::steady_clock::now() > give_up) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}

// The progress line's ETA needs the recording's frame count: the summary's count of the colour
// channel, and without a summary (a recording cut short) the colour messages counted.
TEST_F(LivePipeline, FrameCountFromTheSummaryOrCountedWithoutOne) {
  std::uint64_t frames = 0;
  io::for_each_recorded_frame(recording(), [&](const io::RecordedFrame&) { ++frames; });
  ASSERT_GT(frames, 40u);
  EXPECT_EQ(RecordingSource::frame_count(recording()), frames);
  // The first half of the file: no summary, fewer colour messages, none of them invented.
  const std::string cut = dir_->file("office_cut.mcap");
  std::filesystem::copy_file(recording(), cut, std::filesystem::copy_options::overwrite_existing);
  std::filesystem::resize_file(cut, std::filesystem::file_size(recording()) / 2);
  const std::uint64_t counted = RecordingSource::frame_count(cut);
  EXPECT_GT(counted, 0u);
  EXPECT_LT(counted, frames);
  std::uint64_t intact = 0;
  io::for_each_recorded_frame(cut, [&](const io::RecordedFrame&) { ++intact; });
  EXPECT_GE(counted, intact);  // every colour message, even one whose depth was cut off
  std::filesystem::remove(cut);
}

TEST_F(LivePipeline, LockstepEqualsReplayAndRepeats) {
  const config::RobotConfig cfg = live_config();
  LiveOptions o;
  o.recording = recording();
  o.lockstep = true;
  o.mapping = true;
  const LiveResult a = run_live(cfg, o);
  const LiveResult b = run_live(cfg, o);
  const ReplayResult ref = replay_recording(recording(), cfg, {});
  ASSERT_EQ(a.replay.frames.size(), ref.frames.size());
  ASSERT_EQ(b.replay.frames.size(), ref.frames.size());
  EXPECT_EQ(a.drops, 0u);
  EXPECT_EQ(a.tracker.skipped, 0u);
  EXPECT_EQ(a.source.frame_drops + a.source.imu_drops, 0u);
  EXPECT_EQ(a.tracker.imu_samples, ref.imu_samples_fed);
  for (std::size_t i = 0; i < ref.frames.size(); ++i) {
    ASSERT_EQ(a.replay.frames[i].t_ns, ref.frames[i].t_ns) << i;
    ASSERT_TRUE(same_pose(a.replay.frames[i].T_w_c, ref.frames[i].T_w_c)) << "frame " << i;
    ASSERT_TRUE(same_pose(b.replay.frames[i].T_w_c, a.replay.frames[i].T_w_c)) << "frame " << i;
  }
  // Mapping ran beside it and got every keyframe.
  ASSERT_NE(a.replay.map, nullptr);
  EXPECT_GT(a.replay.map->size(), 0u);
  // its memory was read after the mapper stopped, for the map it left
  EXPECT_EQ(a.replay.map_memory.gaussians, a.replay.map->size());
  EXPECT_GE(a.replay.map_memory.map_params_bytes, a.replay.map->capacity_bytes());
  EXPECT_GT(a.replay.map_memory.keyframes_bytes, 0u);
  EXPECT_DOUBLE_EQ(a.replay.map_bytes_per_gaussian, a.replay.map_memory.bytes_per_gaussian());
  EXPECT_EQ(a.tracker.keyframe_drops, 0u);
  EXPECT_EQ(static_cast<long>(a.tracker.keyframes), a.replay.counters.keyframes);
}

// tracking.loop_closure on vigs run's mapper thread: with loop candidates only a second old
// (the 4 s clip never comes back), the clip's walk is "closed" against its start, and the
// corrected trajectory is vigs replay's (the mapper's one GICP thread sums in another order
// than replay's two, so to 1e-6, not bit for bit); the poses as tracked are kept apart.
TEST_F(LivePipeline, LockstepLoopClosureOnTheMapperThreadMatchesReplay) {
  config::RobotConfig cfg = live_config();
  cfg.tracking.loop.enabled = true;
  cfg.tracking.loop.min_age_s = 1.0;
  cfg.tracking.loop.anchor_spacing_m = 0.2;
  LiveOptions o;
  o.recording = recording();
  o.lockstep = true;
  o.mapping = true;
  const LiveResult a = run_live(cfg, o);
  const ReplayResult ref = replay_recording(recording(), cfg, {});
  ASSERT_TRUE(a.replay.loop.has_value());
  ASSERT_TRUE(ref.loop.has_value());
  EXPECT_GT(a.replay.loop->closures, 0);
  EXPECT_EQ(a.replay.loop->closures, ref.loop->closures);
  EXPECT_EQ(a.replay.loop->keyframes, ref.loop->keyframes);
  ASSERT_EQ(a.replay.frames.size(), ref.frames.size());
  ASSERT_EQ(a.replay.frames_odometry.size(), ref.frames.size());
  bool any_moved = false;
  for (std::size_t i = 0; i < ref.frames.size(); ++i) {
    ASSERT_TRUE(same_pose(a.replay.frames_odometry[i], ref.frames_odometry[i])) << "frame " << i;
    ASSERT_TRUE(a.replay.frames[i].T_w_c.isApprox(ref.frames[i].T_w_c, 1e-6)) << "frame " << i;
    any_moved = any_moved || !same_pose(a.replay.frames[i].T_w_c, a.replay.frames_odometry[i]);
  }
  EXPECT_TRUE(any_moved) << "the closures corrected nothing";
}

// With rt.pin_cpus the tracker's team member 1 is the table's `tracker_w1`, pinned to the CPU
// the tracker does not use. (It was once made by the pinned tracker thread with a default spec
// and inherited the tracker's CPU: the two members took turns on one CPU.)
TEST_F(LivePipeline, TrackerTeamWorkerRunsAsTheThreadTableSays) {
  if (std::thread::hardware_concurrency() < 2) GTEST_SKIP() << "one CPU";
  config::RobotConfig cfg = live_config();
  cfg.rt.pin_cpus = true;
  LiveOptions o;
  o.recording = recording();
  o.lockstep = true;
  o.max_frames = 5;
  const LiveResult r = run_live(cfg, o);
  ASSERT_TRUE(r.tracker_worker.has_value());
  const rt::ThreadSpec& table = rt::thread_spec("tracker_w1");
  EXPECT_EQ(r.tracker_worker->name.view(), "tracker_w1");
  EXPECT_EQ(r.tracker_worker->cpu, table.cpu);
  EXPECT_NE(r.tracker_worker->cpu, rt::thread_spec("tracker").cpu);
  EXPECT_EQ(r.tracker_worker_status.affinity, rt::ApplyResult::kApplied)
      << r.tracker_worker_status.describe();
  // rt.realtime_priorities is off here: the table's priority is not asked for.
  EXPECT_EQ(r.tracker_worker->sched_fifo_priority, 0);
  // The DDS publisher's thread follows rt: too (pinned as the table says, no priority), and
  // with rt.pin_cpus off it is not pinned.
  ASSERT_TRUE(r.publisher_thread.has_value());
  EXPECT_EQ(r.publisher_thread->name.view(), "dds_pub");
  EXPECT_EQ(r.publisher_thread->cpu, rt::thread_spec("dds_pub").cpu);
  EXPECT_EQ(r.publisher_thread->sched_fifo_priority, 0);
  cfg.rt.pin_cpus = false;
  const LiveResult unpinned = run_live(cfg, o);
  ASSERT_TRUE(unpinned.publisher_thread.has_value());
  EXPECT_EQ(unpinned.publisher_thread->cpu, -1);
}

TEST_F(LivePipeline, RealTimeKeepsOrderAndCountsSkips) {
  const config::RobotConfig cfg = live_config();
  LiveOptions o;
  o.recording = recording();
  const LiveResult r = run_live(cfg, o);
  const std::size_t n_recorded = replay_recording(recording(), cfg, {}).frames.size();
  ASSERT_GT(r.replay.frames.size(), 0u);
  // Every recorded frame was either tracked or counted as dropped or skipped.
  EXPECT_EQ(
      r.replay.frames.size() + r.tracker.skipped + r.source.frame_drops + r.tracker.waiting_imu,
      n_recorded);
  for (std::size_t i = 1; i < r.replay.frames.size(); ++i)
    ASSERT_GT(r.replay.frames[i].t_ns, r.replay.frames[i - 1].t_ns);
  // Paced by the stamps: it cannot run faster than the sequence.
  EXPECT_LE(r.real_time_factor, 1.05);
  // the steady part is paced by the stamps too, and measured (not the whole run's figure)
  ASSERT_TRUE(r.real_time_factor_steady);
  EXPECT_LE(*r.real_time_factor_steady, 1.05);
  EXPECT_GT(*r.real_time_factor_steady, 0.0);
  EXPECT_GT(r.tracker_cycles, 0u);
}

TEST_F(LivePipeline, StopRequestDrainsAndReturns) {
  const config::RobotConfig cfg = live_config();
  std::atomic<int> stop{0};
  LiveOptions o;
  o.recording = recording();
  o.stop = &stop;
  std::thread stopper([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    stop.store(15);
  });
  const LiveResult r = run_live(cfg, o);
  stopper.join();
  EXPECT_TRUE(r.stopped_by_signal);
  EXPECT_GT(r.replay.frames.size(), 0u);
  EXPECT_LT(r.stream_s, 3.5);  // stopped before the 4 s sequence ended
}

TEST_F(LivePipeline, SubscriberInAnotherProcessGetsEveryPoseInOrder) {
  const dds::test::ShmJanitor janitor;
  config::RobotConfig cfg = live_config();
  cfg.dds.enabled = true;
  constexpr int kDomain = 171;
  LiveOptions o;
  o.recording = recording();  // real time: a pose every 50 ms, as from the sensors
  o.dds_domain = kDomain;
  o.wait_for_subscribers = 1;
  dds::test::ChildProcess echo(
      {VIGS_BIN, "echo", "rt/vigs/pose", "--domain", std::to_string(kDomain), "--timeout", "0"});
  dds::test::OutputDrainer drainer(echo);  // while the run lasts
  const LiveResult r = run_live(cfg, o);
  drainer.stop();
  const std::size_t n = r.replay.frames.size();
  ASSERT_GT(n, 10u);  // under load the tracker skips frames; every pose it makes must arrive
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(::kill(echo.pid(), SIGINT), 0);
  ASSERT_EQ(echo.wait(std::chrono::seconds(20)), 0) << echo.output();
  // One JSON line per pose with header.stamp {sec, nanosec}; in order, the frames' stamps.
  std::istringstream lines(echo.output());
  std::string line;
  std::size_t i = 0;
  while (std::getline(lines, line)) {
    if (line.find("\"stamp\"") == std::string::npos) continue;
    ASSERT_LT(i, n);
    const std::int64_t t = r.replay.frames[i].t_ns;
    const std::string sec = "\"sec\":" + std::to_string(t / 1'000'000'000);
    const std::string nsec = "\"nanosec\":" + std::to_string(t % 1'000'000'000);
    EXPECT_NE(line.find(sec), std::string::npos) << i << ": " << line;
    EXPECT_NE(line.find(nsec), std::string::npos) << i << ": " << line;
    ++i;
  }
  EXPECT_EQ(i, n);
  EXPECT_EQ(r.poses_published, n);
}

TEST_F(LivePipeline, SigtermMidRunLeavesCompleteResults) {
  const dds::test::ShmJanitor janitor;
  const std::string out = dir_->file("results_sigterm");
  // With the report: it is drawn into the staging folder, so it is saved on a signal too.
  dds::test::ChildProcess run({VIGS_BIN, "run", "--source", "replay:" + recording(), "--out", out,
                               "--dds-domain", "172", "--quiet"},
                              {}, /*merge_stderr=*/true);
  std::this_thread::sleep_for(std::chrono::milliseconds(2500));
  ASSERT_EQ(::kill(run.pid(), SIGTERM), 0);
  ASSERT_EQ(run.wait(std::chrono::seconds(30)), 0) << run.output();
  expect_whole_results(out, /*map=*/true, /*report=*/true);
  const std::string stats = read_text(out + "/stats.json");
  EXPECT_NE(stats.find("\"stopped_by_signal\": true"), std::string::npos) << stats;
  EXPECT_NE(run.output().find("\"ate_rmse_m\""), std::string::npos) << run.output();
  expect_no_staging_left(out);
}

TEST_F(LivePipeline, RunIntoAReusedFolderLeavesNoStaleFile) {
  const dds::test::ShmJanitor janitor;
  const std::string out = dir_->file("results_reused");
  const auto earlier_run = [&] {
    std::filesystem::create_directories(out + "/plots");
    for (const char* name :
         {"trajectory.tum", "map.ply", "report.md", "plots/ate.png", "from_an_earlier_run.txt"})
      write_text(out + "/" + name, "stale");
  };
  const auto vigs_run = [&](const std::vector<std::string>& extra) {
    std::vector<std::string> argv{
        VIGS_BIN,   "run",      "--source", "replay:" + recording(), "--lockstep",
        "--no-map", "--frames", "20",       "--dds-domain",          "173",
        "--quiet",  "--out",    out};
    argv.insert(argv.end(), extra.begin(), extra.end());
    dds::test::ChildProcess run(argv, {}, /*merge_stderr=*/true);
    EXPECT_EQ(run.wait(std::chrono::seconds(60)), 0) << run.output();
  };
  // With the report: a new report.md and plots, nothing of the earlier run's.
  earlier_run();
  vigs_run({});
  expect_whole_results(out, /*map=*/false, /*report=*/true);
  EXPECT_NE(read_text(out + "/trajectory.tum"), "stale");
  EXPECT_NE(read_text(out + "/report.md"), "stale");
  for (const char* name : {"map.ply", "plots/ate.png", "from_an_earlier_run.txt"})
    EXPECT_FALSE(std::filesystem::exists(out + "/" + name)) << name;
  expect_no_staging_left(out);
  // --no-report: not even an earlier report stays.
  earlier_run();
  vigs_run({"--no-report"});
  expect_whole_results(out, /*map=*/false, /*report=*/false);
  for (const char* name : {"map.ply", "report.md", "plots", "from_an_earlier_run.txt"})
    EXPECT_FALSE(std::filesystem::exists(out + "/" + name)) << name;
  expect_no_staging_left(out);
}

TEST_F(LivePipeline, TwoQuickSignalsExitAtOnceAndLeaveNoPartialFolder) {
  const dds::test::ShmJanitor janitor;
  const std::string out = dir_->file("results_two_signals");
  dds::test::ChildProcess run({VIGS_BIN, "run", "--source", "replay:" + recording(), "--out", out,
                               "--dds-domain", "174", "--quiet"},
                              {}, /*merge_stderr=*/true);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_EQ(::kill(run.pid(), SIGTERM), 0);
  // The second once the first was taken (else the kernel merges the two), while the first's
  // drain and save (about half a second here) still run.
  ASSERT_TRUE(wait_signal_taken(run.pid(), SIGTERM, std::chrono::seconds(5)));
  signal_child(run.pid(), SIGTERM);
  // The status proves it: the handler's _exit, not the save's exit 0 (not timed: no speed
  // assertion in a test)
  const int status = run.wait(std::chrono::seconds(10));
  EXPECT_EQ(status, 128 + SIGTERM) << run.output();
  if (std::filesystem::exists(out)) expect_whole_results(out, /*map=*/true, /*report=*/true);
}

TEST_F(LivePipeline, SecondSignalAsTheFolderAppearsFindsItWhole) {
  // The second signal is sent the moment RESULTS_DIR exists: whatever the process still had to
  // write then is lost, so the folder must have been complete (report.md and plots included)
  // when it appeared.
  const dds::test::ShmJanitor janitor;
  const std::string out = dir_->file("results_second_signal");
  dds::test::ChildProcess run({VIGS_BIN, "run", "--source", "replay:" + recording(), "--out", out,
                               "--dds-domain", "175", "--quiet"},
                              {}, /*merge_stderr=*/true);
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  ASSERT_EQ(::kill(run.pid(), SIGTERM), 0);
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!std::filesystem::exists(out) && std::chrono::steady_clock::now() < give_up)
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  ASSERT_TRUE(std::filesystem::exists(out)) << run.output();
  signal_child(run.pid(), SIGTERM);
  const int status = run.wait(std::chrono::seconds(10));
  EXPECT_TRUE(status == 128 + SIGTERM || status == 0) << status << "\n" << run.output();
  expect_whole_results(out, /*map=*/true, /*report=*/true);
}

TEST_F(LivePipeline, RobotFileWithADeviceCameraRunsItsSensorsWithoutSource) {
  // `vigs run --config ROBOT.yaml` on a robot whose camera is a device (camera.driver openni2)
  // opens that robot's sensors; it does not simulate the built-in default sequence. With no
  // device here it stops at once on the serial port, naming it, and writes no RESULTS_DIR.
  const dds::test::ShmJanitor janitor;
  std::string yaml =
      read_text(std::string(VIGS_SOURCE_DIR) + "/firmware_config/robots/xtion_serial_imu.yaml");
  const std::string tty = dir_->file("no_such_tty");
  const auto replace = [&yaml](const std::string& from, const std::string& to) {
    const std::size_t at = yaml.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    yaml.replace(at, from.size(), to);
  };
  replace("port: /dev/ttyUSB0", "port: " + tty);
  replace("interface_ip: 192.168.1.20", "interface_ip: 127.0.0.1");  // loopback only
  replace("dds:\n", "dds:\n  qos_profiles: " + std::string(VIGS_SOURCE_DIR) +
                        "/firmware_config/dds/qos_profiles.xml\n");
  const std::string cfg = dir_->file("xtion_here.yaml"), out = dir_->file("results_device");
  write_text(cfg, yaml);
  dds::test::ChildProcess run(
      {VIGS_BIN, "run", "--config", cfg, "--out", out, "--dds-domain", "176", "--quiet"}, {},
      /*merge_stderr=*/true);
  EXPECT_EQ(run.wait(std::chrono::seconds(30)), 1) << run.output();
  EXPECT_NE(run.output().find("serial port " + tty), std::string::npos) << run.output();
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace vigs::pipeline
