// PoseSample / StatusSnapshot -> ROS 2 messages: stamps, frames, covariance layout, twist frame,
// non-finite values rejected. No DDS traffic.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "dds/pose_messages.hpp"
#include "dds/ros_time.hpp"
#include "dds/status_message.hpp"
#include "pose_pattern.hpp"

namespace vigs::dds {
namespace {

TEST(RosTime, SplitsIntegerNanosecondsExactly) {
  const auto t = to_ros_time(test::kT0Ns);
  ASSERT_TRUE(t);
  EXPECT_EQ(t->sec, 1'700'000'000);
  EXPECT_EQ(t->nanosec, 123'456'789u);
  EXPECT_EQ(to_ns(t->sec, t->nanosec), test::kT0Ns);
  const auto neg = to_ros_time(-1);
  ASSERT_TRUE(neg);
  EXPECT_EQ(neg->sec, -1);
  EXPECT_EQ(neg->nanosec, 999'999'999u);
  EXPECT_EQ(to_ns(neg->sec, neg->nanosec), -1);
  EXPECT_FALSE(to_ros_time(std::numeric_limits<std::int64_t>::max()));
  EXPECT_TRUE(to_ros_time(std::int64_t{2'147'483'647} * 1'000'000'000));
  EXPECT_FALSE(to_ros_time(std::int64_t{2'147'483'648} * 1'000'000'000));
}

TEST(PoseMessages, PoseCarriesSensorStampMapFrameAndRowMajorCovariance) {
  const PoseSample s = test::pattern_sample(7);
  geometry_msgs::msg::dds_::PoseWithCovarianceStamped_ m;
  ASSERT_TRUE(fill_pose(s, {"map", "cam"}, m));
  EXPECT_EQ(to_ns(m.header().stamp().sec(), m.header().stamp().nanosec()), s.t_ns);
  EXPECT_EQ(m.header().frame_id(), "map");
  for (int k = 0; k < 36; ++k) EXPECT_EQ(m.pose().covariance()[k], s.covariance[k]);
  EXPECT_EQ(m.pose().pose().position().y(), s.p_w_m[1]);
  EXPECT_EQ(m.pose().pose().orientation().w(), s.q_w_xyzw[3]);
}

TEST(PoseMessages, OdometryTwistIsInTheCameraFrame) {
  PoseSample s;
  s.t_ns = 5;
  // Camera yawed +90 deg in the world: world +x is camera -y.
  s.q_w_xyzw[2] = std::sqrt(0.5);
  s.q_w_xyzw[3] = std::sqrt(0.5);
  s.v_w_mps[0] = 1.0;
  s.omega_c_radps[1] = 0.3;
  nav_msgs::msg::dds_::Odometry_ o;
  ASSERT_TRUE(fill_odometry(s, {"map", "cam"}, o));
  EXPECT_EQ(o.header().frame_id(), "map");
  EXPECT_EQ(o.child_frame_id(), "cam");
  EXPECT_NEAR(o.twist().twist().linear().x(), 0.0, 1e-12);
  EXPECT_NEAR(o.twist().twist().linear().y(), -1.0, 1e-12);
  EXPECT_EQ(o.twist().twist().angular().y(), 0.3);
  for (double c : o.twist().covariance()) EXPECT_EQ(c, 0.0);
}

TEST(PoseMessages, TfIsMapToCamera) {
  const PoseSample s = test::pattern_sample(3);
  tf2_msgs::msg::dds_::TFMessage_ t;
  ASSERT_TRUE(fill_tf(s, {"world", "camera_link"}, t));
  ASSERT_EQ(t.transforms().size(), 1u);
  EXPECT_EQ(t.transforms()[0].header().frame_id(), "world");
  EXPECT_EQ(t.transforms()[0].child_frame_id(), "camera_link");
  EXPECT_EQ(t.transforms()[0].transform().translation().x(), s.p_w_m[0]);
  EXPECT_EQ(t.transforms()[0].transform().rotation().z(), s.q_w_xyzw[2]);
}

TEST(PoseMessages, PoseQualityCarriesThePoseHeaderSourceFlagsAndKeyframe) {
  PoseSample s = test::pattern_sample(10);
  s.source = PoseSource::kImuPropagated;
  s.flags = kPoseFlagImuUnavailable | kPoseFlagMapRestarted;
  vigs_msgs::msg::dds_::PoseQuality_ q;
  ASSERT_TRUE(fill_pose_quality(s, {"world", "cam"}, q));
  EXPECT_EQ(to_ns(q.header().stamp().sec(), q.header().stamp().nanosec()), s.t_ns);
  EXPECT_EQ(q.header().frame_id(), "world");  // the pose's frame
  EXPECT_EQ(q.frame_index(), 10u);
  EXPECT_EQ(q.source(), vigs_msgs::msg::PoseQuality_Constants::SOURCE_IMU_PROPAGATED);
  EXPECT_EQ(q.flags(), vigs_msgs::msg::PoseQuality_Constants::FLAG_IMU_UNAVAILABLE |
                           vigs_msgs::msg::PoseQuality_Constants::FLAG_MAP_RESTARTED);
  EXPECT_TRUE(q.keyframe());
  // A sample whose pose is not published has no quality either.
  s.p_w_m[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(fill_pose_quality(s, {}, q));
}

TEST(PoseMessages, NonFiniteValuesOrUnrepresentableStampsAreNotPublished) {
  geometry_msgs::msg::dds_::PoseWithCovarianceStamped_ m;
  nav_msgs::msg::dds_::Odometry_ o;
  PoseSample s = test::pattern_sample(1);
  s.covariance[20] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(fill_pose(s, {}, m));
  s = test::pattern_sample(1);
  s.v_w_mps[2] = std::numeric_limits<double>::infinity();
  EXPECT_FALSE(fill_odometry(s, {}, o));
  s = test::pattern_sample(1);
  s.t_ns = std::numeric_limits<std::int64_t>::max();
  EXPECT_FALSE(publishable(s));
  EXPECT_TRUE(publishable(test::pattern_sample(1)));
}

TEST(StatusMessage, CopiesTablesClampsCountsAndZeroesNonFinite) {
  StatusSnapshot s;
  s.t_ns = test::kT0Ns;
  s.tracking_state = TrackingState::kImuOnly;
  s.gaussian_count = 123456;
  s.mapping_budget_used = std::numeric_limits<double>::quiet_NaN();
  s.thread_count = 99;  // more than the table holds
  for (std::size_t i = 0; i < StatusSnapshot::kMaxThreads; ++i) {
    set_name(s.threads[i].name, "a_thread_name_that_is_much_longer_than_thirty_two_bytes");
  }
  s.ring_count = 1;
  set_name(s.rings[0].name, "imu->tracker");
  s.rings[0].drops = 4;
  s.fault_count = 1;
  set_name(s.faults[0].name, "imu.checksum_errors");
  s.faults[0].count = 2;
  vigs_msgs::msg::dds_::Status_ m;
  ASSERT_TRUE(fill_status(s, "robo", "map", m));
  EXPECT_EQ(m.robot(), "robo");
  EXPECT_EQ(m.tracking_state(), 2);
  EXPECT_EQ(m.gaussian_count(), 123456u);
  EXPECT_EQ(m.mapping_budget_used(), 0.0);
  ASSERT_EQ(m.threads().size(), StatusSnapshot::kMaxThreads);
  EXPECT_EQ(m.threads()[0].name().size(), kStatusNameLength - 1);
  ASSERT_EQ(m.rings().size(), 1u);
  EXPECT_EQ(m.rings()[0].name(), "imu->tracker");
  EXPECT_EQ(m.rings()[0].drops(), 4u);
  ASSERT_EQ(m.faults().size(), 1u);
  EXPECT_EQ(m.faults()[0].count(), 2u);
  EXPECT_EQ(to_ns(m.header().stamp().sec(), m.header().stamp().nanosec()), test::kT0Ns);
}

}  // namespace
}  // namespace vigs::dds
