// Publisher (PosePublisher in a second process, tests/dds/dds_pose_source.cpp) to our
// Subscriber: every pose arrives, in order, with its sensor stamp, frame ids and covariance
// layout, on pose, odom, tf and keyframe; status arrives; each pose's quality (pose_quality:
// same header, frame index, every PoseSource and every PoseFlags combination, keyframe bit)
// arrives exactly. Over shared memory and over UDP loopback only. Unique domain ids: 151, 152.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include "dds/dds_config.hpp"
#include "dds/ros_time.hpp"
#include "dds/subscriber.hpp"
#include "pose_pattern.hpp"
#include "process.hpp"
#include "shm_janitor.hpp"

namespace vigs::dds {
namespace {

using namespace std::chrono_literals;
using geometry_msgs::msg::dds_::PoseStamped_;
using geometry_msgs::msg::dds_::PoseWithCovarianceStamped_;
using nav_msgs::msg::dds_::Odometry_;
using tf2_msgs::msg::dds_::TFMessage_;
using vigs_msgs::msg::dds_::PoseQuality_;
using vigs_msgs::msg::dds_::Status_;

constexpr int kCount = 100;

struct Received {
  std::mutex m;
  std::vector<PoseWithCovarianceStamped_> poses;
  std::vector<Odometry_> odoms;
  std::vector<TFMessage_> tfs;
  std::vector<PoseStamped_> keyframes;
  std::vector<Status_> statuses;
  std::vector<PoseQuality_> qualities;
  std::size_t pose_count() {
    std::lock_guard l(m);
    return poses.size();
  }
};

void expect_stamp(const std_msgs::msg::dds_::Header_& h, std::int64_t t_ns, const char* frame) {
  EXPECT_EQ(to_ns(h.stamp().sec(), h.stamp().nanosec()), t_ns);
  EXPECT_LT(h.stamp().nanosec(), 1'000'000'000u);
  EXPECT_EQ(h.frame_id(), frame);
}

void run_pair(int domain, bool shm) {
  test::ShmJanitor janitor;
  DdsConfig cfg = default_dds_config(domain);
  cfg.shared_memory = shm;
  Received r;
  {
    Subscriber sub(cfg, "test_two_process_sub");
    sub.subscribe<PoseQuality_>(cfg.topics.pose_quality, [&](const auto& m) {
      std::lock_guard l(r.m);
      r.qualities.push_back(m);
    });
    sub.subscribe<PoseWithCovarianceStamped_>(cfg.topics.pose, [&](const auto& m) {
      std::lock_guard l(r.m);
      r.poses.push_back(m);
    });
    sub.subscribe<Odometry_>(cfg.topics.odom, [&](const auto& m) {
      std::lock_guard l(r.m);
      r.odoms.push_back(m);
    });
    sub.subscribe<TFMessage_>(cfg.topics.tf, [&](const auto& m) {
      std::lock_guard l(r.m);
      r.tfs.push_back(m);
    });
    sub.subscribe<PoseStamped_>(cfg.topics.keyframe, [&](const auto& m) {
      std::lock_guard l(r.m);
      r.keyframes.push_back(m);
    });
    sub.subscribe<Status_>(cfg.topics.status, [&](const auto& m) {
      std::lock_guard l(r.m);
      r.statuses.push_back(m);
    });
    test::ChildProcess pub({VIGS_DDS_POSE_SOURCE, "--domain", std::to_string(domain), "--count",
                            std::to_string(kCount), "--rate-hz", "100", "--shm", shm ? "1" : "0",
                            "--wait-quality", "1"});
    ASSERT_EQ(pub.wait(90s), 0) << pub.output();
    for (int i = 0; i < 300 && r.pose_count() < kCount; ++i) std::this_thread::sleep_for(10ms);
    EXPECT_NE(pub.output().find("\"ring_drops\":0"), std::string::npos) << pub.output();
  }
  std::lock_guard l(r.m);
  ASSERT_EQ(r.poses.size(), static_cast<std::size_t>(kCount));
  ASSERT_EQ(r.odoms.size(), static_cast<std::size_t>(kCount));
  ASSERT_EQ(r.tfs.size(), static_cast<std::size_t>(kCount));
  ASSERT_EQ(r.qualities.size(), static_cast<std::size_t>(kCount));
  std::uint32_t sources_seen = 0, flags_seen = 0;
  for (int i = 0; i < kCount; ++i) {
    const PoseSample s = test::pattern_sample(static_cast<std::uint64_t>(i));
    const auto& p = r.poses[static_cast<std::size_t>(i)];
    expect_stamp(p.header(), s.t_ns, "map");
    EXPECT_EQ(p.pose().pose().position().x(), s.p_w_m[0]);
    EXPECT_EQ(p.pose().pose().position().y(), s.p_w_m[1]);
    EXPECT_EQ(p.pose().pose().orientation().z(), s.q_w_xyzw[2]);
    EXPECT_EQ(p.pose().pose().orientation().w(), s.q_w_xyzw[3]);
    for (int k = 0; k < 36; ++k) {
      ASSERT_EQ(p.pose().covariance()[static_cast<std::size_t>(k)], s.covariance[k])
          << "pose " << i << " covariance[" << k << "]";
    }
    const auto& o = r.odoms[static_cast<std::size_t>(i)];
    expect_stamp(o.header(), s.t_ns, "map");
    EXPECT_EQ(o.child_frame_id(), "camera");
    const Eigen::Quaterniond q(s.q_w_xyzw[3], s.q_w_xyzw[0], s.q_w_xyzw[1], s.q_w_xyzw[2]);
    const Eigen::Vector3d v_c = q.conjugate() * Eigen::Vector3d(0.1, 0.2, 0.3);
    EXPECT_NEAR(o.twist().twist().linear().x(), v_c.x(), 1e-12);
    EXPECT_NEAR(o.twist().twist().linear().y(), v_c.y(), 1e-12);
    EXPECT_EQ(o.twist().twist().angular().z(), 0.2);
    const auto& t = r.tfs[static_cast<std::size_t>(i)];
    ASSERT_EQ(t.transforms().size(), 1u);
    expect_stamp(t.transforms()[0].header(), s.t_ns, "map");
    EXPECT_EQ(t.transforms()[0].child_frame_id(), "camera");
    EXPECT_EQ(t.transforms()[0].transform().translation().y(), s.p_w_m[1]);
    const auto& pq = r.qualities[static_cast<std::size_t>(i)];
    expect_stamp(pq.header(), s.t_ns, "map");
    EXPECT_EQ(pq.frame_index(), s.frame_index);
    EXPECT_EQ(pq.source(), static_cast<std::uint8_t>(s.source)) << "pose " << i;
    EXPECT_EQ(pq.flags(), s.flags) << "pose " << i;
    EXPECT_EQ(pq.keyframe(), s.keyframe) << "pose " << i;
    sources_seen |= 1u << pq.source();
    flags_seen |= pq.flags();
  }
  // The pattern went through every source and every flag bit (so each reached the subscriber).
  EXPECT_EQ(sources_seen, 0b1111u);
  EXPECT_EQ(flags_seen, kPoseFlagDegenerate | kPoseFlagImuUnavailable | kPoseFlagFramesSkipped |
                            kPoseFlagOutOfOrder | kPoseFlagMapRestarted | kPoseFlagImuCorrupt |
                            kPoseFlagCameraReopened);
  ASSERT_EQ(r.keyframes.size(), static_cast<std::size_t>(kCount / 10));
  for (std::size_t j = 0; j < r.keyframes.size(); ++j) {
    expect_stamp(r.keyframes[j].header(), test::pattern_sample(10 * j).t_ns, "map");
  }
  ASSERT_FALSE(r.statuses.empty());
  EXPECT_EQ(r.statuses.back().robot(), "test_robot");
  ASSERT_EQ(r.statuses.back().threads().size(), 1u);
  EXPECT_EQ(r.statuses.back().threads()[0].name(), "tracker");
  EXPECT_EQ(r.statuses.back().tracking_state(), 1);
}

TEST(DdsTwoProcess, EveryPoseArrivesInOrderOverSharedMemory) {
  run_pair(151, true);
}
TEST(DdsTwoProcess, EveryPoseArrivesInOrderOverUdpLoopback) {
  run_pair(152, false);
}

}  // namespace
}  // namespace vigs::dds
