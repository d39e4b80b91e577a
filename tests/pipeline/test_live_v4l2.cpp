// `vigs run --source live` with camera.driver v4l2 (issue #14): the live spine (run_live) with a
// V4L2 RGB-D camera -- a fake Z16 depth node and YUYV colour node with the kernel's semantics
// behind the driver's device seam (tests/drivers/fake_v4l2_device.hpp; no video device here) --
// and a serial Xsens IMU on a real pseudo-terminal; with the GPIO frame trigger (its kernel
// event records written into a pipe, as tests/drivers/test_gpio_trigger.cpp) and without.
// The scene is static: a room corner (floor, back and side wall) seen by a camera at rest.
// Checked: frames flow through the V4L2 driver into the tracker and out as poses; with the
// trigger the `gpio_trigger` thread runs, counts every edge and each tracked frame carries its
// edge's stamp; recorded (`vigs run --record`), the edges are in the file; every pipeline thread
// is gone once run_live returns. DDS on loopback, domains 186-188.
#include <dirent.h>
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/gpio.h>
#include <linux/videodev2.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "../dds/shm_janitor.hpp"
#include "drivers/serial_imu/pseudo_terminal.hpp"
#include "drivers/serial_imu/xsens_encoder.hpp"
#include "fake_v4l2_device.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/ros_msgs/time_reference.hpp"
#include "io/ros_msgs/typed_io.hpp"
#include "pipeline/live_pipeline.hpp"
#include "record/recorder.hpp"
#include "rt/clock.hpp"
#include "sim_sequence.hpp"
#include "tests/common/test_pipe.hpp"

namespace vigs::pipeline {
namespace {

using drivers::testing::FakeV4l2Device;

const std::string kDepthNode = "/dev/v4l/by-id/fake-rgbd-depth";
const std::string kColourNode = "/dev/v4l/by-id/fake-rgbd-colour";
// One DDS domain per test (ctest runs them in parallel): 186, 187, 188.
constexpr int kDomain = 186;
constexpr int kFrames = 60;       // 3 s at 20 Hz
constexpr int kImuPerFrame = 10;  // 200 Hz
// The strobe's edge comes at the exposure's start, 1 ms before the frame's (start of frame)
// stamp; the frame itself arrives 20 ms later, after its exposure and transfer.
constexpr std::int64_t kEdgeLeadNs = 1'000'000;
constexpr int kTransferImuPeriods = 4;

// The names of this process's threads now (/proc/self/task/*/comm).
std::multiset<std::string> thread_names() {
  std::multiset<std::string> out;
  DIR* d = ::opendir("/proc/self/task");
  if (d == nullptr) return out;
  while (const dirent* e = ::readdir(d)) {
    if (e->d_name[0] == '.') continue;
    std::ifstream comm(std::string("/proc/self/task/") + e->d_name + "/comm");
    std::string name;
    if (std::getline(comm, name)) out.insert(name);
  }
  ::closedir(d);
  return out;
}

// The pipeline's own threads (rt/thread_table.hpp) that must not outlive run_live.
const char* const kPipelineThreads[] = {"gpio_trigger", "imu_driver", "rgbd_driver",
                                        "tracker",      "tracker_w1", "mapper",
                                        "mapper_w1",    "dds_pub",    "recorder"};

// A camera at rest in a room corner: back wall 4 m ahead, floor 1.2 m below, a wall 1.5 m to the
// left (camera frame: x right, y down, z forward). Depth in raw units of depth_scale_m.
std::vector<std::uint8_t> corner_depth_z16(const config::CameraSettings& c) {
  const auto w = static_cast<std::uint32_t>(c.width_px),
             h = static_cast<std::uint32_t>(c.height_px);
  std::vector<std::uint8_t> bytes(std::size_t{w} * h * 2);
  for (std::uint32_t v = 0; v < h; ++v) {
    for (std::uint32_t u = 0; u < w; ++u) {
      const double x = (u - c.cx_px) / c.fx_px, y = (v - c.cy_px) / c.fy_px;  // ray (x, y, 1)
      double z_m = 4.0;
      if (y > 0) z_m = std::min(z_m, 1.2 / y);
      if (x < 0) z_m = std::min(z_m, -1.5 / x);
      const auto raw = static_cast<std::uint16_t>(std::lround(z_m / c.depth_scale_m));
      std::memcpy(&bytes[(std::size_t{v} * w + u) * 2], &raw, 2);
    }
  }
  return bytes;
}

// A grey ramp, YUYV (Y0 U Y1 V).
std::vector<std::uint8_t> ramp_yuyv(const config::CameraSettings& c) {
  const auto w = static_cast<std::uint32_t>(c.width_px),
             h = static_cast<std::uint32_t>(c.height_px);
  std::vector<std::uint8_t> bytes(std::size_t{w} * h * 2);
  for (std::uint32_t v = 0; v < h; ++v) {
    for (std::uint32_t u = 0; u < w; ++u) {
      std::uint8_t* p = &bytes[(std::size_t{v} * w + u) * 2];
      p[0] = static_cast<std::uint8_t>(16 + (3 * u + 5 * v) % 220);
      p[1] = 128;
    }
  }
  return bytes;
}

struct RunOutcome {
  LiveResult result;
  std::set<std::int64_t> edge_stamps_ns;   // every edge written
  std::set<std::int64_t> frame_stamps_ns;  // every frame the fake camera delivered, as V4L2 has it
  int frames_pushed = 0;
  std::set<std::string> threads_seen;  // while running (the progress callback)
  std::multiset<std::string> threads_after;
};

// run_live on the fake V4L2 camera (+ the trigger's pipe) and the pty IMU for kFrames frames;
// recording into `record_path` (`vigs run --record`) unless it is empty.
RunOutcome run_fake_live(bool trigger, int domain, const std::string& record_path = {}) {
  const dds::test::ShmJanitor janitor;
  drivers::PseudoTerminal pty;
  // A pipeline that failed reads nothing: a full pty then drops bytes instead of blocking.
  EXPECT_EQ(::fcntl(pty.master_fd(), F_SETFL, ::fcntl(pty.master_fd(), F_GETFL) | O_NONBLOCK), 0);
  test::GpioEventPipe edges;
  EXPECT_GE(edges.r, 0);

  config::RobotConfig cfg = testing::live_test_config(kFrames / 20.0);
  cfg.camera.driver = "v4l2";
  cfg.camera.device = kDepthNode;
  cfg.camera.colour_device = kColourNode;
  cfg.camera.colour_format = "YUYV";
  cfg.camera.rate_hz = 20.0;
  if (trigger) {
    cfg.camera.trigger_chip = "gpiochip7";  // never opened: the pipe stands in for its line
    cfg.camera.trigger_line = 17;
    cfg.camera.trigger_offset_ms = 0.0;
    cfg.camera.trigger_tolerance_ms = 3.0;
  }
  cfg.imu.driver = "serial";
  cfg.imu.port = pty.slave_path();
  cfg.imu.protocol = "xsens_mt";
  cfg.imu.rate_hz = 200.0;
  cfg.dds.enabled = true;

  const auto w = static_cast<std::uint32_t>(cfg.camera.width_px);
  const auto h = static_cast<std::uint32_t>(cfg.camera.height_px);
  FakeV4l2Device fake;
  fake.add_node(kDepthNode, {.pixelformat = V4L2_PIX_FMT_Z16,
                             .width = w,
                             .height = h,
                             .bytes_per_line = w * 2,
                             .size_image = w * h * 2});
  fake.add_node(kColourNode, {.pixelformat = V4L2_PIX_FMT_YUYV,
                              .width = w,
                              .height = h,
                              .bytes_per_line = w * 2,
                              .size_image = w * h * 2});

  LiveOptions o;
  o.mapping = false;
  o.dds_domain = domain;
  o.record_path = record_path;
  o.camera_seams.v4l2_ops = &fake;
  if (trigger) o.camera_seams.trigger_event_fd = edges.r;
  std::atomic<int> stop{0};
  o.stop = &stop;

  RunOutcome out;
  // The sensors: once the camera streams, IMU messages at 200 Hz on the pty, and every 10th an
  // edge, its frame 20 ms later; then stop the run.
  std::thread sensors([&] {
    const auto depth = corner_depth_z16(cfg.camera);
    const auto colour = ramp_yuyv(cfg.camera);
    const std::int64_t give_up = rt::monotonic_ns() + rt::s_to_ns(std::int64_t{30});
    while (!(fake.streaming(kDepthNode) && fake.streaming(kColourNode)) &&
           rt::monotonic_ns() < give_up && stop.load() == 0) {
      rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(5));
    }
    const std::int64_t period_ns = rt::ms_to_ns(5);
    const std::int64_t t0 = rt::monotonic_ns();
    std::int64_t edge_ns = t0;
    for (int k = 0; k < kFrames * kImuPerFrame && stop.load() == 0; ++k) {
      rt::sleep_until_ns(t0 + k * period_ns);
      const auto msg = drivers::xsens::encode_mtdata2(static_cast<std::uint32_t>(k * 50),
                                                      {0.0, 0.0, 9.81}, {0.0, 0.0, 0.0});
      (void)pty.write_all(msg);
      if (k % kImuPerFrame == 0) {
        edge_ns = rt::monotonic_ns();
        if (trigger) {
          if (edges.write_edge(edge_ns)) out.edge_stamps_ns.insert(edge_ns);
        }
      }
      if (k % kImuPerFrame != kTransferImuPeriods) continue;
      const std::int64_t t_ns = edge_ns + kEdgeLeadNs;
      const bool depth_ok = fake.push_frame(kDepthNode, {.bytes = depth, .t_ns = t_ns});
      const bool colour_ok = fake.push_frame(kColourNode, {.bytes = colour, .t_ns = t_ns});
      if (depth_ok && colour_ok) {
        ++out.frames_pushed;
        out.frame_stamps_ns.insert(t_ns - t_ns % 1000);  // a timeval: whole microseconds
      }
    }
    rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(300));  // the last frames tracked
    stop.store(1);
  });
  try {
    out.result = run_live(cfg, o, [&](const LiveProgress&) {
      for (const std::string& n : thread_names()) out.threads_seen.insert(n);
    });
  } catch (const std::exception& e) {
    ADD_FAILURE() << "run_live threw: " << e.what();
    stop.store(1);
  }
  sensors.join();
  out.threads_after = thread_names();
  return out;
}

void expect_frames_tracked_and_threads_joined(const RunOutcome& o) {
  const LiveResult& r = o.result;
  EXPECT_TRUE(r.stopped_by_signal);
  // The V4L2 driver delivered the fake camera's frames into the pipeline's ring...
  ASSERT_TRUE(r.camera_driver.has_value()) << "no camera driver ran";
  EXPECT_GE(o.frames_pushed, kFrames / 2);
  EXPECT_GE(r.camera_driver->delivered, static_cast<std::uint64_t>(o.frames_pushed / 2));
  EXPECT_EQ(r.camera_driver->opens, 1u);
  EXPECT_EQ(r.camera_driver->losses, 0u);
  // ... the IMU driver read the pty ...
  ASSERT_TRUE(r.imu_driver.has_value());
  EXPECT_GT(r.imu_driver->samples_out, static_cast<std::uint64_t>(kFrames * kImuPerFrame / 2));
  // ... and the tracker made poses of them, published on DDS.
  const std::size_t n = r.replay.frames.size();
  EXPECT_GT(n, 0u) << "poses recorded";  // how many depends on the machine's load
  EXPECT_GT(r.poses_published, 0u);
  EXPECT_LE(n, r.camera_driver->delivered);
  std::printf("v4l2 live: %d frames pushed, %llu delivered, %zu tracked, %llu published\n",
              o.frames_pushed, static_cast<unsigned long long>(r.camera_driver->delivered), n,
              static_cast<unsigned long long>(r.poses_published));
  // Every pipeline thread was seen running and none is left.
  for (const char* name : {"rgbd_driver", "imu_driver", "tracker", "dds_pub"}) {
    EXPECT_TRUE(o.threads_seen.count(name)) << name << " never ran";
  }
  for (const char* name : kPipelineThreads) {
    EXPECT_EQ(o.threads_after.count(name), 0u) << name << " outlived run_live";
  }
}

TEST(LiveV4l2, FramesFromAV4l2CameraAndGpioTriggerReachTheTracker) {
  const RunOutcome o = run_fake_live(true, kDomain);
  expect_frames_tracked_and_threads_joined(o);
  const LiveResult& r = o.result;
  // The gpio_trigger thread ran, read every edge, and the frames were restamped with them.
  EXPECT_TRUE(o.threads_seen.count("gpio_trigger")) << "the trigger thread never ran";
  ASSERT_TRUE(r.trigger.has_value() && r.trigger_match.has_value());
  EXPECT_EQ(r.trigger->rising, o.edge_stamps_ns.size());
  EXPECT_EQ(r.trigger->pushed, o.edge_stamps_ns.size());
  EXPECT_EQ(r.trigger->read_errors, 0u);
  // The matcher accounted for every frame; an edge read late (a loaded machine: nothing here is
  // real-time) leaves its frame with the frame's own stamp, so how many match is the load's.
  const drivers::TriggerMatchCounters& m = *r.trigger_match;
  EXPECT_EQ(m.matched + m.frames_without_edge, r.camera_driver->frames_read);
  EXPECT_GT(m.matched, 0u);
  std::size_t on_edge = 0;
  for (const TrackedFrame& f : r.replay.frames) on_edge += o.edge_stamps_ns.count(f.t_ns);
  EXPECT_GT(on_edge, 0u) << "tracked frames stamped with their edges";
}

// `vigs run --record` with the frame sync writes its edges as `vigs record` does: one
// /vigs/camera/trigger TimeReference per edge read, stamped with it, source "chip:line".
TEST(LiveV4l2, RecordingALiveRunKeepsTheTriggerEdges) {
  const testing::TempDir dir;
  const std::string path = dir.file("run.mcap");
  const RunOutcome o = run_fake_live(true, kDomain + 2, path);
  const LiveResult& r = o.result;
  ASSERT_TRUE(r.trigger.has_value() && r.record.has_value());
  EXPECT_EQ(r.trigger->tap_dropped, 0u);
  EXPECT_EQ(r.record->written.edges, r.trigger->rising);
  io::mcap::McapReader reader(path);
  io::mcap::MessageView m;
  std::set<std::int64_t> recorded_ns;
  while (reader.next(m)) {
    if (m.channel->topic != record::kTriggerTopic) continue;
    io::ros_msgs::TimeReference ref;
    ASSERT_TRUE(io::ros_msgs::decode_message(m, ref));
    EXPECT_EQ(ref.source, "gpiochip7:17");
    EXPECT_EQ(static_cast<std::int64_t>(m.log_time_ns), ref.time_ref.to_ns());
    recorded_ns.insert(ref.time_ref.to_ns());
  }
  EXPECT_TRUE(reader.issues().empty());
  EXPECT_EQ(recorded_ns.size(), r.trigger->rising);
  EXPECT_FALSE(recorded_ns.empty());
  // The kernel's stamps of the edges the pipe carried, to the nanosecond.
  for (const std::int64_t t_ns : recorded_ns) EXPECT_EQ(o.edge_stamps_ns.count(t_ns), 1u) << t_ns;
}

TEST(LiveV4l2, FramesFromAV4l2CameraWithoutTriggerKeepTheirKernelStamps) {
  const RunOutcome o = run_fake_live(false, kDomain + 1);
  expect_frames_tracked_and_threads_joined(o);
  const LiveResult& r = o.result;
  EXPECT_FALSE(r.trigger.has_value());
  EXPECT_FALSE(o.threads_seen.count("gpio_trigger")) << "no trigger configured";
  std::size_t kernel_stamped = 0;
  for (const TrackedFrame& f : r.replay.frames) kernel_stamped += o.frame_stamps_ns.count(f.t_ns);
  EXPECT_EQ(kernel_stamped, r.replay.frames.size());
}

}  // namespace
}  // namespace vigs::pipeline
