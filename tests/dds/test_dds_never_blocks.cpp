// The pose ring's producer never waits for DDS: with no subscriber at all, and with a reliable
// subscriber that matched and then stopped (SIGSTOP, a hung peer), the publisher thread keeps
// draining the ring and writing, so nothing is dropped. With dds.enabled false the ring is
// drained and discarded. A control run with a blocking QoS shows the check can fail.
// Domains 156-158, 166.
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

struct StoppedRun {
  int ring_drops = 0;
  PosePublisher::Stats stats;
};

// A reliable reader in a second process matches, then is stopped (SIGSTOP) while the producer
// pushes; the publisher must keep up.
StoppedRun run_with_stopped_subscriber(const DdsConfig& cfg) {
  StoppedRun out;
  rt::SpscRing<PoseSample> ring(1024);
  PosePublisher pub(cfg, ring);
  pub.start();
  test::ChildProcess sink({VIGS_DDS_POSE_SINK, "--domain", std::to_string(cfg.domain_id), "--count",
                           "1000000", "--timeout-s", "120"});
  for (int i = 0; i < 3000 && pub.pose_subscribers() < 1; ++i) std::this_thread::sleep_for(10ms);
  EXPECT_EQ(pub.pose_subscribers(), 1) << "the sink never matched";
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(kill(sink.pid(), SIGSTOP), 0);
  out.ring_drops = produce(ring);
  pub.stop();
  out.stats = pub.stats();
  kill(sink.pid(), SIGCONT);
  kill(sink.pid(), SIGTERM);
  sink.wait(10s);
  return out;
}

TEST(DdsNeverBlocks, StoppedReliableSubscriber) {
  test::ShmJanitor janitor;
  // Reopening the stopped reader's shared-memory port waits dds.shm_peer_check_ms inside
  // write(); at Fast DDS's 1 s, two such waits overflow this test's 1 kHz ring (seen in CI).
  DdsConfig cfg = default_dds_config(157);
  cfg.shm_peer_check_ms = 50;
  const StoppedRun r = run_with_stopped_subscriber(cfg);
  EXPECT_EQ(r.ring_drops, 0);
  EXPECT_EQ(r.stats.poses_published, static_cast<std::uint64_t>(kPushes));
  EXPECT_EQ(r.stats.write_errors, 0u);
}

// Control: the same run with a QoS whose writes do wait for acknowledgements (KEEP_ALL, 20
// samples, 50 ms blocking) must show it, so the test above can fail.
TEST(DdsNeverBlocks, ControlBlockingQosIsDetected) {
  test::ShmJanitor janitor;
  DdsConfig cfg = default_dds_config(166);
  cfg.qos_source = "test_dds_never_blocks blocking profiles";
  cfg.qos_xml = R"(<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns="http://www.eprosima.com/XMLSchemas/fastRTPS_Profiles">
  <profiles>
    <data_writer profile_name="blocking_pose">
      <qos><reliability><kind>RELIABLE</kind>
        <max_blocking_time><sec>0</sec><nanosec>50000000</nanosec></max_blocking_time>
      </reliability></qos>
      <topic><historyQos><kind>KEEP_ALL</kind></historyQos>
        <resourceLimitsQos><max_samples>20</max_samples><max_instances>1</max_instances>
          <max_samples_per_instance>20</max_samples_per_instance></resourceLimitsQos></topic>
    </data_writer>
    <data_writer profile_name="blocking_other"/>
    <data_reader profile_name="blocking_reader"/>
  </profiles>
</dds>
)";
  cfg.pose_qos_profile = "blocking_pose";
  cfg.keyframe_qos_profile = "blocking_other";
  cfg.status_qos_profile = "blocking_other";
  cfg.reader_qos_profile = "blocking_reader";
  const StoppedRun r = run_with_stopped_subscriber(cfg);
  EXPECT_TRUE(r.ring_drops > 0 || r.stats.write_errors > 0)
      << "drops " << r.ring_drops << ", write errors " << r.stats.write_errors;
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
