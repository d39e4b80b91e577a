// The tracker task does not allocate after warm-up. This binary replaces global operator new
// (../common/counting_new.hpp) and counts the calls made inside LiveTracker::tick (on the test
// thread, which plays the `tracker` periodic task) and on the tracker's worker thread
// (`tracker_w1`), once 40 frames have been tracked, over the next 200 frames of a simulated
// office with walking people (the point count changes every frame) in lockstep, in both
// fusion modes, with IMU guesses, keyframes handed to a mapper slot queue, and driver fault
// counts growing on another thread (corrupt IMU bytes, camera losses: poses flagged). The first
// few offending call sites are kept and printed (`addr2line -Cfe FILE OFFSET` names them).
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

#include "../common/counting_new.hpp"
#include "lockstep_tracker_rig.hpp"
#include "pipeline/keyframe_handoff.hpp"
#include "pipeline/live_tracker.hpp"
#include "pipeline/recording_source.hpp"
#include "sim_sequence.hpp"

namespace {

thread_local bool t_in_tick = false;
std::atomic<bool> g_armed{false};
std::atomic<long> g_allocations{0};
std::array<std::atomic<void*>, 8> g_callers{};

}  // namespace

namespace vigs::test {

void on_operator_new(std::size_t /*bytes*/, void* caller) noexcept {
  if (!g_armed.load(std::memory_order_relaxed)) return;
  if (!t_in_tick && !on_thread_named("tracker_w1")) return;
  const long k = g_allocations.fetch_add(1);
  if (k < static_cast<long>(g_callers.size())) g_callers[static_cast<std::size_t>(k)] = caller;
}

}  // namespace vigs::test

namespace vigs::pipeline {
namespace {

constexpr std::uint64_t kWarmUpFrames = 40;
constexpr std::uint64_t kCountedFrames = 200;

class TrackerAllocation : public ::testing::TestWithParam<const char*> {};

// The drivers' fault totals, raised by the consumer thread as a driver's thread would.
struct GrowingDriverFaults final : DriverFaultCounts {
  [[nodiscard]] std::uint64_t imu_corrupt() const noexcept override {
    return imu.load(std::memory_order_relaxed);
  }
  [[nodiscard]] std::uint64_t camera_losses() const noexcept override {
    return camera.load(std::memory_order_relaxed);
  }
  std::atomic<std::uint64_t> imu{0}, camera{0};
};

TEST_P(TrackerAllocation, NoAllocationAfterWarmUpOver200Frames) {
  g_allocations = 0;
  config::RobotConfig cfg = testing::small_office(13.0);  // 260 frames
  cfg.sim.humans = 8;
  cfg.tracking.fusion = GetParam();
  testing::TempDir dir;
  const std::string path = dir.file("office.mcap");
  testing::simulate(cfg, path);

  GrowingDriverFaults driver_faults;
  testing::LockstepTrackerRig rig(cfg, path, 16, &driver_faults);
  rt::FramePool& pool = rig.pool;
  KeyframeHandoff& handoff = rig.handoff;
  auto& poses = rig.poses;
  auto& results = rig.results;
  LiveTracker& tracker = rig.tracker;

  // The mapper's, the publisher's and the main thread's sides, on one consumer thread.
  std::atomic<bool> consume{true};
  std::uint64_t results_seen = 0;
  std::uint64_t poses_driver_flagged = 0;
  std::thread consumer([&] {
    while (consume.load()) {
      std::uint32_t index = 0;
      while (handoff.next(index)) {
        if (index == KeyframeHandoff::kEnd) continue;
        pool.release(handoff.slot(index).frame);
        handoff.give_back(index);
      }
      PoseSample p;
      while (poses.try_pop(p)) {
        poses_driver_flagged += (p.flags & (kPoseFlagImuCorrupt | kPoseFlagCameraReopened)) != 0;
      }
      LiveFrameResult r;
      while (results.try_pop(r)) {
        if (r.end_of_stream) continue;
        // Armed from the 41st result to the 240th: a lockstep tick tracks as many frames as
        // the source keeps queuing, so the count is kept here, not between ticks.
        ++results_seen;
        if (results_seen % 7 == 0) driver_faults.imu.fetch_add(1, std::memory_order_relaxed);
        if (results_seen % 11 == 0) driver_faults.camera.fetch_add(1, std::memory_order_relaxed);
        if (results_seen == kWarmUpFrames) g_armed = true;
        if (results_seen == kWarmUpFrames + kCountedFrames) g_armed = false;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  });

  while (!tracker.done() && !tracker.failed()) {
    t_in_tick = true;
    tracker.tick();
    t_in_tick = false;
  }
  g_armed = false;
  consume = false;
  consumer.join();
  rig.source.stop();
  ASSERT_FALSE(tracker.failed()) << tracker.failure_message();
  const LiveTrackerCounters c = tracker.counters();
  ASSERT_GE(results_seen, kWarmUpFrames + kCountedFrames) << "the sequence is too short";
  EXPECT_GT(c.keyframes, 5u) << "keyframes must be made while counting";
  EXPECT_GT(poses_driver_flagged, 20u) << "driver faults must flag poses while counting";
  const OdometryCounters oc = tracker.odometry_counters();
  EXPECT_GT(oc.imu_guesses, 200);
  const long n = g_allocations.load();
  for (long k = 0; k < std::min<long>(n, static_cast<long>(g_callers.size())); ++k) {
    void* caller = g_callers[static_cast<std::size_t>(k)].load();
    Dl_info info{};
    const auto base = ::dladdr(caller, &info) != 0
                          ? reinterpret_cast<std::uintptr_t>(info.dli_fbase)
                          : std::uintptr_t{0};
    std::printf("allocation %ld from %s+0x%zx\n", k, info.dli_fname ? info.dli_fname : "?",
                static_cast<std::size_t>(reinterpret_cast<std::uintptr_t>(caller) - base));
  }
  EXPECT_EQ(n, 0) << "operator new calls on the tracker's threads after " << kWarmUpFrames
                  << " frames";
}

INSTANTIATE_TEST_SUITE_P(Fusion, TrackerAllocation, ::testing::Values("paper", "fused"));

}  // namespace
}  // namespace vigs::pipeline
