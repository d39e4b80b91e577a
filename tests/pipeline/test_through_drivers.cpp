// `vigs run --source replay:F.mcap --through-drivers` (pipeline/driver_replay.hpp): a short
// simulated office sequence (240x160, 5 s) played through the REAL drivers in real time -- an
// .oni clip through OpenNI2 and the Openni2Driver, Xsens MT bytes on a pseudo-terminal through
// the SerialImuDriver -- into the live pipeline:
//  - end to end: a subscriber in a second process (`vigs echo`) gets every published pose in
//    order, stamped in the host clock at exactly the recorded frame time plus the run's
//    host-minus-recording offset; the trajectory maps back onto the recorded frame stamps and
//    its ATE is within the lockstep replay's bound (tests/pipeline/test_odometry.cpp);
//  - faults injected by the feeder, each counted and flagged, none stopping the run: the IMU
//    silent for 1 s (and a subscriber in another process sees each pose's flags and source on
//    the pose_quality topic), corrupted serial bytes (the poses after them flagged IMU-corrupt,
//    on DDS too, and the status topic says so), the camera lost and back (the first pose after
//    it flagged camera-reopened, the loss in the status). (A frame out of order cannot leave the
//    OpenNI2 driver, whose DeviceClock keeps stamps increasing; the tracker's own policy and its
//    status count are tested in test_live_tracker_faults.cpp.)
// DDS domains 181-184, loopback, shared-memory segments cleaned up.
#include <gtest/gtest.h>

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "../dds/process.hpp"
#include "../dds/shm_janitor.hpp"
#include "io/json_text.hpp"
#include "pipeline/live_pipeline.hpp"
#include "pipeline/pose_quality.hpp"
#include "sim_sequence.hpp"

namespace vigs::pipeline {
namespace {

constexpr double kSeconds = 5.0;
constexpr std::int64_t kS = 1'000'000'000;

config::RobotConfig drivers_config() {
  return testing::live_test_config(kSeconds);
}

class ThroughDrivers : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new testing::TempDir();
    testing::simulate(drivers_config(), dir_->file("office.mcap"));
    motion_ = new RecordedMotion(read_recorded_motion(recording()));
    const ReplayResult ref = replay_recording(recording(), drivers_config(), {});
    stamps_ = new std::vector<std::int64_t>();
    for (const TrackedFrame& f : ref.frames) stamps_->push_back(f.t_ns);
  }
  static void TearDownTestSuite() {
    delete stamps_;
    delete motion_;
    delete dir_;
  }
  static std::string recording() { return dir_->file("office.mcap"); }
  static LiveOptions options() {
    LiveOptions o;
    o.recording = recording();
    o.through_drivers = true;
    return o;
  }
  static std::int64_t first_stamp() { return stamps_->front(); }

  static testing::TempDir* dir_;
  static RecordedMotion* motion_;
  static std::vector<std::int64_t>* stamps_;  // every recorded frame
};
testing::TempDir* ThroughDrivers::dir_ = nullptr;
RecordedMotion* ThroughDrivers::motion_ = nullptr;
std::vector<std::int64_t>* ThroughDrivers::stamps_ = nullptr;

std::vector<io::Json> json_lines(const std::string& text) {
  std::vector<io::Json> out;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] != '{') continue;
    out.push_back(io::Json::parse(line));
  }
  return out;
}

TEST_F(ThroughDrivers, EveryPoseReachesAnotherProcessInOrderAndTheAteHolds) {
  const dds::test::ShmJanitor janitor;
  config::RobotConfig cfg = drivers_config();
  cfg.dds.enabled = true;
  constexpr int kDomain = 181;
  LiveOptions o = options();
  o.dds_domain = kDomain;
  o.wait_for_subscribers = 1;
  dds::test::ChildProcess echo(
      {VIGS_BIN, "echo", "rt/vigs/pose", "--domain", std::to_string(kDomain), "--timeout", "0"});
  dds::test::OutputDrainer drainer(echo);
  const LiveResult r = run_live(cfg, o);
  drainer.stop();
  const std::size_t n = r.replay.frames.size();
  ASSERT_GT(n, 40u) << "of " << stamps_->size() << " frames";
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(::kill(echo.pid(), SIGINT), 0);
  ASSERT_EQ(echo.wait(std::chrono::seconds(20)), 0) << echo.output();

  // The drivers ran: every frame came through OpenNI2 (but those its real-time player replaced
  // before the driver thread, not real-time in tests, read them), every IMU sample through the
  // pty.
  ASSERT_TRUE(r.camera_driver && r.imu_driver);
  // (A skipped colour frame leaves its depth frame unpaired.)
  const drivers::RgbdDriverCounters& cam = *r.camera_driver;
  EXPECT_LE(cam.frames_read, stamps_->size());
  EXPECT_GE(cam.frames_read + cam.playback_skipped + cam.unpaired, stamps_->size());
  EXPECT_LE(cam.playback_skipped + cam.unpaired, stamps_->size() / 20);
  EXPECT_TRUE(r.camera_driver->end_of_stream);
  // (The run ends with the camera's last frame: the feeder may not have sent the IMU's last
  // samples, and the driver may not have read the last bytes, when they are stopped.)
  EXPECT_GE(r.feeder.imu_samples_written + 5, motion_->imu.size());
  EXPECT_LE(r.imu_driver->samples_out, r.feeder.imu_samples_written);
  EXPECT_GE(r.imu_driver->samples_out + 2, r.feeder.imu_samples_written);
  EXPECT_EQ(r.imu_driver->bad_checksum + r.imu_driver->sample_counter_gap, 0u);
  // Clean drivers flag no pose with their faults.
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(r.pose_flags[i] & (kPoseFlagImuCorrupt | kPoseFlagCameraReopened), 0u) << i;
  }
  // Every frame read was tracked, skipped, dropped at the camera ring, or waited for the IMU.
  EXPECT_EQ(n + r.tracker.skipped + r.source.frame_drops + r.tracker.waiting_imu,
            r.camera_driver->frames_read);
  // The IMU's stamps line up with the frames' (an IMU clock 100 ms behind would flag them all);
  // on a loaded machine without real-time priorities a few frames may find it late.
  EXPECT_LE(r.tracker.imu_unavailable, n / 10);

  // Back in the recording's clock: each pose is stamped at its recorded frame's time, in order.
  const std::set<std::int64_t> recorded(stamps_->begin(), stamps_->end());
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_TRUE(recorded.count(r.replay.frames[i].t_ns)) << i << ": " << r.replay.frames[i].t_ns;
    if (i > 0) {
      ASSERT_GT(r.replay.frames[i].t_ns, r.replay.frames[i - 1].t_ns);
    }
  }
  // The subscriber got each one, in order, stamped in the host clock (frame time + offset).
  EXPECT_NE(r.host_minus_recording_ns, 0);
  std::size_t i = 0;
  for (const io::Json& line : json_lines(echo.output())) {
    ASSERT_LT(i, n);
    const io::Json& stamp = line["msg"]["header"]["stamp"];
    const std::int64_t t =
        stamp["sec"].get<std::int64_t>() * kS + stamp["nanosec"].get<std::int64_t>();
    EXPECT_EQ(t, r.replay.frames[i].t_ns + r.host_minus_recording_ns) << "pose " << i;
    ++i;
  }
  EXPECT_EQ(i, n);
  EXPECT_EQ(r.poses_published, n);

  // Accuracy. The lockstep replay's bound for this sequence is 3 cm (test_odometry.cpp), and
  // an unloaded run through the drivers measured 0.0065 m here. In real time a loaded machine
  // makes the tracker skip frames (half of them beside the other live tests at ctest -j2,
  // 0.041 m), so the bound is 8 cm. (The ATE barely sees the IMU's timing: with the IMU
  // written 50 ms late it measured the same 0.0065 m; the stamps above check the clocks.)
  const eval::AteResult ate = testing::camera_ate(*motion_, r.replay.frames, cfg);
  std::printf("through the drivers: %zu of %zu frames, ATE rmse %.4f m, real-time factor %.2f\n", n,
              stamps_->size(), ate.stats.rmse, r.real_time_factor);
  EXPECT_LT(ate.stats.rmse, 0.08);
}

TEST_F(ThroughDrivers, ImuSilentForOneSecondIsFlaggedAndRecovers) {
  const dds::test::ShmJanitor janitor;
  config::RobotConfig cfg = drivers_config();
  cfg.dds.enabled = true;
  constexpr int kDomain = 182;
  LiveOptions o = options();
  o.mapping = false;
  o.dds_domain = kDomain;
  o.wait_for_subscribers = 1;
  o.driver_faults.imu_pause_at_ns = 2 * kS;
  o.driver_faults.imu_pause_ns = 1 * kS;
  // Every VIGS topic (echo subscribes the pose last: matched, the pose_quality reader is too).
  dds::test::ChildProcess echo(
      {VIGS_BIN, "echo", "--domain", std::to_string(kDomain), "--timeout", "0"});
  dds::test::OutputDrainer drainer(echo);
  const LiveResult r = run_live(cfg, o);
  drainer.stop();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(::kill(echo.pid(), SIGINT), 0);
  ASSERT_EQ(echo.wait(std::chrono::seconds(20)), 0) << echo.output();
  ASSERT_TRUE(r.imu_driver);
  // The feeder sent nothing for 1 s (200 samples at 200 Hz); the driver saw the counter jump.
  EXPECT_NEAR(static_cast<double>(r.feeder.imu_samples_withheld), 200.0, 1.0);
  EXPECT_GE(r.imu_driver->sample_counter_gap, 1u);
  EXPECT_NEAR(static_cast<double>(r.imu_driver->samples_missed),
              static_cast<double>(r.feeder.imu_samples_withheld), 1.0);
  // Frames in the silence are flagged and counted; frames after it are not (a loaded machine
  // without real-time priorities may delay a few IMU reads past a frame: at most a fifth); the
  // run went on.
  const std::int64_t from = first_stamp() + 2 * kS, to = from + 1 * kS;
  std::size_t flagged = 0, before = 0, flagged_before = 0, after = 0, flagged_after = 0;
  std::int64_t recovered_at = 0;  // first unflagged frame after the silence
  for (std::size_t i = 0; i < r.replay.frames.size(); ++i) {
    const std::int64_t t = r.replay.frames[i].t_ns;
    const bool flag = (r.pose_flags[i] & kPoseFlagImuUnavailable) != 0;
    if (t > from + kS / 5 && t <= to) flagged += flag;
    if (t > to && !flag && recovered_at == 0) recovered_at = t;
    if (t > to + kS / 5) {
      ++after;
      flagged_after += flag;
    }
    if (t <= from) {
      ++before;
      flagged_before += flag;
    }
  }
  EXPECT_LE(flagged_before * 5, before);
  EXPECT_LE(flagged_after * 5, after);
  EXPECT_GT(recovered_at, 0);
  EXPECT_LE(recovered_at, to + kS / 2) << "recovered within half a second";
  EXPECT_GE(flagged, 5u);
  EXPECT_EQ(r.tracker.imu_unavailable,
            static_cast<std::uint64_t>(
                std::count_if(r.pose_flags.begin(), r.pose_flags.end(),
                              [](std::uint32_t f) { return (f & kPoseFlagImuUnavailable) != 0; })));
  EXPECT_GE(after, 10u);
  EXPECT_FALSE(r.stopped_by_signal);
  EXPECT_TRUE(r.camera_driver->end_of_stream);

  // On DDS, in another process: one PoseQuality per published pose, in order, with the pose's
  // stamp, its frame index, source and exactly the flags the pipeline recorded, so the poses
  // of the silence arrive flagged IMU-unavailable. The status carries the pose counts.
  std::size_t i = 0, flagged_on_dds = 0;
  bool status_counts = false;
  for (const io::Json& line : json_lines(echo.output())) {
    if (line["topic"] == "rt/vigs/status") {
      for (const io::Json& f : line["msg"]["faults"])
        status_counts = status_counts || f["name"] == "tracker.poses_imu_propagated";
    }
    if (line["topic"] != "rt/vigs/pose_quality") continue;
    ASSERT_LT(i, r.replay.frames.size());
    const io::Json& m = line["msg"];
    const std::int64_t t = m["header"]["stamp"]["sec"].get<std::int64_t>() * kS +
                           m["header"]["stamp"]["nanosec"].get<std::int64_t>();
    EXPECT_EQ(t, r.replay.frames[i].t_ns + r.host_minus_recording_ns) << "pose " << i;
    EXPECT_EQ(m["frame_index"].get<std::uint64_t>(), i);
    EXPECT_EQ(m["source"].get<int>(), static_cast<int>(pose_source(r.replay.frames[i], i)))
        << "pose " << i;
    const auto flags = m["flags"].get<std::uint32_t>();
    EXPECT_EQ(flags, r.pose_flags[i]) << "pose " << i;
    flagged_on_dds += (flags & kPoseFlagImuUnavailable) != 0;
    ++i;
  }
  EXPECT_EQ(i, r.replay.frames.size());
  EXPECT_EQ(r.poses_published, r.replay.frames.size());
  EXPECT_EQ(flagged_on_dds, r.tracker.imu_unavailable);
  EXPECT_GE(flagged_on_dds, 5u);
  EXPECT_TRUE(status_counts) << "no status with tracker.poses_imu_propagated";
}

TEST_F(ThroughDrivers, CorruptSerialBytesAreResyncedCountedAndInTheStatus) {
  const dds::test::ShmJanitor janitor;
  config::RobotConfig cfg = drivers_config();
  cfg.dds.enabled = true;
  constexpr int kDomain = 183;
  LiveOptions o = options();
  o.mapping = false;
  o.dds_domain = kDomain;
  o.wait_for_subscribers = 1;
  // Every 10th message (one every 50 ms) from 2 s on: the poses before are clean.
  constexpr std::int64_t kCorruptFromNs = 2 * kS;
  o.driver_faults.corrupt_every = 10;
  o.driver_faults.corrupt_from_ns = kCorruptFromNs;
  // Every VIGS topic (echo subscribes the pose last: matched, the pose_quality reader is too).
  dds::test::ChildProcess echo(
      {VIGS_BIN, "echo", "--domain", std::to_string(kDomain), "--timeout", "0"});
  dds::test::OutputDrainer drainer(echo);
  const LiveResult r = run_live(cfg, o);
  drainer.stop();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(::kill(echo.pid(), SIGINT), 0);
  ASSERT_EQ(echo.wait(std::chrono::seconds(20)), 0) << echo.output();

  ASSERT_TRUE(r.imu_driver);
  const std::uint64_t corrupted = r.feeder.imu_messages_corrupted;
  const std::int64_t corrupt_from = first_stamp() + kCorruptFromNs;
  const auto clean = static_cast<std::uint64_t>(
      std::count_if(motion_->imu.begin(), motion_->imu.end(),
                    [&](const ImuSample& s) { return s.t_ns < corrupt_from; }));
  ASSERT_GT(r.feeder.imu_samples_written, clean);
  EXPECT_EQ(corrupted, (r.feeder.imu_samples_written - clean) / 10);
  EXPECT_GE(corrupted, 35u);
  // Each corrupted message is rejected by its checksum and skipped; every other one arrives
  // (but the last bytes written just before the stop, at most 2 samples).
  EXPECT_GE(r.imu_driver->bad_checksum, corrupted);
  EXPECT_GT(r.imu_driver->resync_bytes_skipped, 0u);
  EXPECT_LE(r.imu_driver->samples_out, r.feeder.imu_samples_written - corrupted);
  EXPECT_GE(r.imu_driver->samples_out + 2, r.feeder.imu_samples_written - corrupted);
  EXPECT_EQ(r.imu_driver->non_finite_sample, 0u);
  // The run went on, tracking with the IMU throughout.
  EXPECT_GT(r.replay.frames.size(), 40u);
  EXPECT_TRUE(r.camera_driver->end_of_stream);
  // The poses say so: none well before the first corrupt message (a pose is flagged when its
  // frame is tracked, some 10-50 ms after its stamp), and after it the first pose after each
  // corrupt message (one every 50 ms, as the frames: most poses, fewer when two messages fall
  // between the same poses, as when the tracker skips a frame).
  std::size_t before = 0, after = 0, flagged_after = 0;
  for (std::size_t i = 0; i < r.replay.frames.size(); ++i) {
    const std::int64_t t = r.replay.frames[i].t_ns;
    const bool flag = (r.pose_flags[i] & kPoseFlagImuCorrupt) != 0;
    if (t < corrupt_from - kS / 5) {
      ++before;
      EXPECT_FALSE(flag) << "pose " << i << ", " << (corrupt_from - t) / 1'000'000
                         << " ms before the first corrupt message";
    }
    if (t > corrupt_from + kS / 5) {
      ++after;
      flagged_after += flag;
    }
  }
  EXPECT_GE(before, 20u);
  EXPECT_GE(after, 20u);
  std::printf("corrupt IMU bytes: %zu of %zu poses after the first flagged, %zu before\n",
              flagged_after, after, before);
  EXPECT_GE(flagged_after * 2, after) << flagged_after << " of " << after << " poses";
  // On DDS, in another process: each pose_quality carries the pose's flags (the corrupt ones
  // included), and the 1 Hz status reports the count.
  std::uint64_t reported = 0;
  std::size_t i = 0, flagged_on_dds = 0;
  for (const io::Json& line : json_lines(echo.output())) {
    if (line["topic"] == "rt/vigs/status") {
      for (const io::Json& f : line["msg"]["faults"])
        if (f["name"] == "imu.bad_checksum")
          reported = std::max(reported, f["count"].get<std::uint64_t>());
    }
    if (line["topic"] != "rt/vigs/pose_quality") continue;
    ASSERT_LT(i, r.replay.frames.size());
    const auto flags = line["msg"]["flags"].get<std::uint32_t>();
    EXPECT_EQ(flags, r.pose_flags[i]) << "pose " << i;
    flagged_on_dds += (flags & kPoseFlagImuCorrupt) != 0;
    ++i;
  }
  EXPECT_EQ(i, r.replay.frames.size());
  EXPECT_EQ(flagged_on_dds, static_cast<std::size_t>(std::count_if(
                                r.pose_flags.begin(), r.pose_flags.end(),
                                [](std::uint32_t f) { return (f & kPoseFlagImuCorrupt) != 0; })));
  EXPECT_GT(reported, 0u) << echo.output();
  EXPECT_LE(reported, r.imu_driver->bad_checksum);
}

TEST_F(ThroughDrivers, CameraLostAndBackIsReopenedAndTrackingGoesOn) {
  const dds::test::ShmJanitor janitor;
  config::RobotConfig cfg = drivers_config();
  cfg.dds.enabled = true;
  constexpr int kDomain = 184;
  LiveOptions o = options();
  o.mapping = false;
  o.dds_domain = kDomain;
  // Gone for 2 s: the stall is seen after 400 ms and the first reopen follows 100 ms later,
  // which leaves the reopen well over a second to find no device even on a loaded machine.
  constexpr std::int64_t kGoneAtNs = 3 * kS / 2, kGoneForNs = 2 * kS;
  o.driver_faults.camera_gone_at_ns = kGoneAtNs;
  o.driver_faults.camera_gone_ns = kGoneForNs;
  dds::test::ChildProcess echo(
      {VIGS_BIN, "echo", "rt/vigs/status", "--domain", std::to_string(kDomain), "--timeout", "0"});
  dds::test::OutputDrainer drainer(echo);
  const LiveResult r = run_live(cfg, o);
  drainer.stop();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ASSERT_EQ(::kill(echo.pid(), SIGINT), 0);
  ASSERT_EQ(echo.wait(std::chrono::seconds(20)), 0) << echo.output();
  ASSERT_TRUE(r.camera_driver);
  const drivers::RgbdDriverCounters& c = *r.camera_driver;
  EXPECT_EQ(r.feeder.camera_returns, 1u);
  EXPECT_GE(c.losses, 1u);
  EXPECT_GE(c.frame_timeouts, 1u);
  EXPECT_GE(c.open_failures, 1u);  // unplugged: no device to reopen until it is back
  EXPECT_GE(c.reopens, 1u);
  EXPECT_TRUE(c.end_of_stream);
  // Frames before the loss and after the return were tracked, in order. The first pose after
  // the loss is flagged camera-reopened, none before it.
  const std::int64_t gone = first_stamp() + kGoneAtNs;
  std::size_t before = 0, after = 0, flagged = 0;
  std::optional<bool> first_after_flagged;
  for (std::size_t i = 0; i < r.replay.frames.size(); ++i) {
    const std::int64_t t = r.replay.frames[i].t_ns;
    if (i > 0) {
      ASSERT_GT(t, r.replay.frames[i - 1].t_ns);
    }
    before += t < gone;
    after +=
        t > gone + kGoneForNs;  // the reopened camera is stamped at least as late as it returns
    const bool flag = (r.pose_flags[i] & kPoseFlagCameraReopened) != 0;
    flagged += flag;
    if (t < gone) {
      EXPECT_FALSE(flag) << "pose " << i << " before the loss";
    }
    if (t >= gone && !first_after_flagged) first_after_flagged = flag;
  }
  EXPECT_GE(before, 10u);
  EXPECT_GE(after, 10u);
  EXPECT_EQ(first_after_flagged, std::optional<bool>(true));
  EXPECT_GE(flagged, 1u);
  EXPECT_LE(flagged, c.losses);
  // The 1 Hz status topic, in another process, reports the loss and the reopen.
  std::uint64_t losses = 0, reopens = 0;
  for (const io::Json& line : json_lines(echo.output())) {
    for (const io::Json& f : line["msg"]["faults"]) {
      if (f["name"] == "camera.losses") losses = std::max(losses, f["count"].get<std::uint64_t>());
      if (f["name"] == "camera.reopens")
        reopens = std::max(reopens, f["count"].get<std::uint64_t>());
    }
  }
  EXPECT_GE(losses, 1u) << echo.output();
  EXPECT_LE(losses, c.losses);
  EXPECT_GE(reopens, 1u) << echo.output();
  EXPECT_LE(reopens, c.reopens);
  // Only the frames before the loss and after the return were read: none twice.
  EXPECT_LT(c.frames_read, stamps_->size());
}

}  // namespace
}  // namespace vigs::pipeline
