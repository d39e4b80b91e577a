// The pose ring's producer never waits for DDS: with no subscriber at all, and with a reliable
// subscriber that matched and then stopped (SIGSTOP, a hung peer), the publisher thread keeps
// draining the ring and writing, so nothing is dropped. With dds.enabled false the ring is
// drained and discarded. Domains 156-158.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <thread>

#include "dds/dds_config.hpp"
#include "dds/pose_publisher.hpp"
#include "pose_pattern.hpp"
#include "process.hpp"
#include "shm_janitor.hpp"

namespace vigs::dds {
namespace {

using namespace std::chrono_literals;

constexpr int kPushes = 2000;

// Pushes kPushes pattern samples at about 1 kHz (50x the camera rate); returns the ring drops.
int produce(rt::SpscRing<PoseSample>& ring) {
  int dropped = 0;
  for (int i = 0; i < kPushes; ++i) {
    if (!ring.try_push(test::pattern_sample(static_cast<std::uint64_t>(i)))) ++dropped;
    std::this_thread::sleep_for(1ms);
  }
  return dropped;
}

TEST(DdsNeverBlocks, NoSubscriber) {
  test::ShmJanitor janitor;
  rt::SpscRing<PoseSample> ring(1024);
  PosePublisher pub(default_dds_config(156), ring);
  pub.start();
  EXPECT_EQ(pub.pose_subscribers(), 0);
  EXPECT_EQ(produce(ring), 0);
  pub.stop();
  const auto st = pub.stats();
  EXPECT_EQ(st.poses_published, static_cast<std::uint64_t>(kPushes));
  EXPECT_EQ(st.keyframes_published, static_cast<std::uint64_t>(kPushes / 10));
  EXPECT_EQ(st.write_errors, 0u);
  ASSERT_NE(pub.task(), nullptr);
  EXPECT_GT(pub.task()->cycles(), 0u);
  EXPECT_EQ(pub.task()->spec().name.view(), "dds_pub");
}

TEST(DdsNeverBlocks, StoppedReliableSubscriber) {
  test::ShmJanitor janitor;
  rt::SpscRing<PoseSample> ring(1024);
  const DdsConfig cfg = default_dds_config(157);
  PosePublisher pub(cfg, ring);
  pub.start();
  test::ChildProcess sink(
      {VIGS_DDS_POSE_SINK, "--domain", "157", "--count", "1000000", "--timeout-s", "120"});
  for (int i = 0; i < 3000 && pub.pose_subscribers() < 1; ++i) std::this_thread::sleep_for(10ms);
  ASSERT_EQ(pub.pose_subscribers(), 1) << "the sink never matched";
  std::this_thread::sleep_for(300ms);
  ASSERT_EQ(kill(sink.pid(), SIGSTOP), 0);
  EXPECT_EQ(produce(ring), 0);
  pub.stop();
  const auto st = pub.stats();
  EXPECT_EQ(st.poses_published, static_cast<std::uint64_t>(kPushes));
  EXPECT_EQ(st.write_errors, 0u);
  kill(sink.pid(), SIGCONT);
  kill(sink.pid(), SIGTERM);
  sink.wait(10s);
}

TEST(DdsNeverBlocks, DisabledDrainsAndDiscards) {
  rt::SpscRing<PoseSample> ring(16);
  DdsConfig cfg = default_dds_config(158);
  cfg.enabled = false;
  PosePublisher pub(cfg, ring);
  EXPECT_FALSE(pub.enabled());
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(ring.try_push(test::pattern_sample(i)));
  EXPECT_EQ(pub.run_cycle(0), 10u);
  EXPECT_EQ(pub.stats().discarded, 10u);
  EXPECT_EQ(pub.stats().poses_published, 0u);
}

}  // namespace
}  // namespace vigs::dds
