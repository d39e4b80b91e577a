// The live tracker hands each keyframe to the mapper with the keyframe's own frame. With the
// moving test on (the default), the tracker holds a keyframe for moving_window_frames frames
// and releases it on a later frame; the frame handed with it must be the held one (same
// stamp: the pool slot the source filled with it), not the frame that released it. Lockstep over a
// simulated office with walking people; the mapper's side is a consumer thread that checks every
// slot.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "lockstep_tracker_rig.hpp"
#include "pipeline/keyframe_handoff.hpp"
#include "pipeline/live_tracker.hpp"
#include "pipeline/recording_source.hpp"
#include "sim_sequence.hpp"

namespace vigs::pipeline {
namespace {

struct HandedKeyframes {
  int total = 0;
  int own_frame = 0;       // the slot's frame carries the keyframe's stamp
  int released_later = 0;  // held: published after frames newer than it were tracked
};

HandedKeyframes run_lockstep(const config::RobotConfig& cfg, const std::string& path,
                             std::size_t pool_slots, std::size_t& pool_free_at_end) {
  testing::LockstepTrackerRig rig(cfg, path, static_cast<std::uint32_t>(pool_slots));
  rt::FramePool& pool = rig.pool;
  KeyframeHandoff& handoff = rig.handoff;
  auto& poses = rig.poses;
  auto& results = rig.results;
  LiveTracker& tracker = rig.tracker;

  HandedKeyframes h;
  std::atomic<std::int64_t> newest_tracked_t_ns{INT64_MIN};
  std::atomic<bool> consume{true};
  // Lockstep: a keyframe is published in the tick that tracked its releasing frame, after
  // that frame's result; so the newest result seen bounds the releasing frame from below.
  const auto drain_results = [&] {
    LiveFrameResult r;
    while (results.try_pop(r)) {
      if (!r.end_of_stream) newest_tracked_t_ns = r.frame.t_ns;
    }
  };
  const auto drain_keyframes = [&] {
    std::uint32_t index = 0;
    while (handoff.next(index)) {
      if (index == KeyframeHandoff::kEnd) continue;
      drain_results();
      KeyframeSlot& slot = handoff.slot(index);
      const rt::Frame& f = pool.frame(slot.frame);
      ++h.total;
      if (f.t_ns == slot.keyframe.t_ns) ++h.own_frame;
      if (slot.keyframe.t_ns < newest_tracked_t_ns.load()) ++h.released_later;
      pool.release(slot.frame);
      handoff.give_back(index);
    }
  };
  std::thread consumer([&] {
    while (consume.load()) {
      PoseSample p;
      while (poses.try_pop(p)) {
      }
      drain_results();
      drain_keyframes();
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  });
  while (!tracker.done() && !tracker.failed()) tracker.tick();
  consume = false;
  consumer.join();
  drain_keyframes();  // the mapper's side takes what the last tick handed over after its stop
  rig.source.stop();
  EXPECT_FALSE(tracker.failed()) << tracker.failure_message();
  EXPECT_EQ(tracker.counters().keyframe_drops, 0u);
  pool_free_at_end = pool.available();
  return h;
}

TEST(LiveTrackerKeyframes, HeldKeyframeKeepsItsOwnFrame) {
  config::RobotConfig cfg = testing::small_office(6.0);
  cfg.sim.humans = 4;
  ASSERT_TRUE(cfg.tracking.moving_test_on()) << "the default holds keyframes";
  testing::TempDir dir;
  const std::string path = dir.file("office.mcap");
  testing::simulate(cfg, path);

  std::size_t free_at_end = 0;
  const std::size_t slots = 16;
  const HandedKeyframes h = run_lockstep(cfg, path, slots, free_at_end);
  ASSERT_GT(h.total, 3) << "keyframes must be made";
  EXPECT_GT(h.released_later, 1) << "keyframes after the first must be held and released later";
  EXPECT_EQ(h.own_frame, h.total) << "every keyframe reaches the mapper with its own frame";
  EXPECT_EQ(free_at_end, slots) << "held frames are released at the end of the stream";
}

}  // namespace
}  // namespace vigs::pipeline
