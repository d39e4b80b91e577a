// Round trip of every message type in both encodings, golden bytes for the CDR and ROS 1
// layouts (alignment, NUL, seq), and decode errors that name the field.
#include <gtest/gtest.h>

#include <cstring>

#include "msg_samples.hpp"

namespace vigs::io {
namespace {

using ros_msgs::Encoding;

template <class Msg>
void expect_round_trip(const Msg& msg, Encoding encoding) {
  std::vector<std::uint8_t> bytes;
  ros_msgs::encode(msg, encoding, bytes);
  Msg back;
  ros_msgs::decode(bytes, encoding, back);
  Msg expected = msg;
  if constexpr (requires { expected.header.seq; }) {
    if (encoding == Encoding::kCdr) expected.header.seq = 0;  // ROS 2 has no seq
  }
  EXPECT_EQ(back, expected) << ros_msgs::type_name<Msg>(encoding);
}

TEST(RosMsgs, EveryTypeRoundTripsInCdrAndRos1) {
  for (Encoding e : {Encoding::kCdr, Encoding::kRos1}) {
    for (int i = 0; i < 3; ++i) {
      expect_round_trip(test::sample_image(i, false), e);
      expect_round_trip(test::sample_image(i, true), e);
      expect_round_trip(test::sample_imu(i), e);
      expect_round_trip(test::sample_camera_info(i), e);
      expect_round_trip(test::sample_pose(i), e);
      expect_round_trip(test::sample_odometry(i), e);
      expect_round_trip(test::sample_serial(i), e);
    }
    expect_round_trip(ros_msgs::Image{}, e);  // empty strings and sequences
    expect_round_trip(ros_msgs::CameraInfo{}, e);
  }
}

template <class T>
T read_at(const std::vector<std::uint8_t>& b, std::size_t at) {
  T v{};
  std::memcpy(&v, b.data() + at, sizeof(T));
  return v;
}

TEST(RosMsgs, PoseStampedCdrLayoutIsXcdr1LittleEndian) {
  ros_msgs::PoseStamped m;
  m.header.stamp = {-3, 7};
  m.header.frame_id = "w";
  m.pose.position = {1, 2, 3};
  m.pose.orientation = {4, 5, 6, 7};
  std::vector<std::uint8_t> b;
  ros_msgs::encode(m, Encoding::kCdr, b);
  // 4 header + sec 4 + nanosec 4 + len 4 + "w\0" 2 + pad 2 (to 8, relative to the header) + 7*8.
  ASSERT_EQ(b.size(), 4u + 16u + 56u);
  EXPECT_EQ(b[0], 0x00);
  EXPECT_EQ(b[1], 0x01);
  EXPECT_EQ(b[2], 0x00);
  EXPECT_EQ(b[3], 0x00);
  EXPECT_EQ(read_at<std::int32_t>(b, 4), -3);
  EXPECT_EQ(read_at<std::uint32_t>(b, 8), 7u);
  EXPECT_EQ(read_at<std::uint32_t>(b, 12), 2u);  // length includes the NUL
  EXPECT_EQ(b[16], 'w');
  EXPECT_EQ(b[17], 0);
  for (int k = 0; k < 7; ++k) EXPECT_EQ(read_at<double>(b, 20 + 8 * k), k + 1.0);
}

TEST(RosMsgs, PoseStampedRos1LayoutIsPackedWithSeq) {
  ros_msgs::PoseStamped m;
  m.header.seq = 9;
  m.header.stamp = {11, 12};
  m.header.frame_id = "w";
  m.pose.position = {1, 2, 3};
  m.pose.orientation = {4, 5, 6, 7};
  std::vector<std::uint8_t> b;
  ros_msgs::encode(m, Encoding::kRos1, b);
  ASSERT_EQ(b.size(), 12u + 4u + 1u + 56u);
  EXPECT_EQ(read_at<std::uint32_t>(b, 0), 9u);
  EXPECT_EQ(read_at<std::uint32_t>(b, 4), 11u);
  EXPECT_EQ(read_at<std::uint32_t>(b, 8), 12u);
  EXPECT_EQ(read_at<std::uint32_t>(b, 12), 1u);  // no NUL in ROS 1
  EXPECT_EQ(b[16], 'w');
  for (int k = 0; k < 7; ++k) EXPECT_EQ(read_at<double>(b, 17 + 8 * k), k + 1.0);
}

TEST(RosMsgs, ImageDataSequenceIsCountPrefixed) {
  const ros_msgs::Image m = test::sample_image(0, false);
  std::vector<std::uint8_t> b;
  ros_msgs::encode(m, Encoding::kCdr, b);
  ASSERT_GE(b.size(), m.data.size() + 4);
  const std::size_t data_at = b.size() - m.data.size();
  EXPECT_EQ(read_at<std::uint32_t>(b, data_at - 4), m.data.size());
  EXPECT_TRUE(std::equal(m.data.begin(), m.data.end(), b.begin() + data_at));
}

TEST(RosMsgs, TruncatedMessageNamesFieldAndOffset) {
  std::vector<std::uint8_t> b;
  ros_msgs::encode(test::sample_image(1, false), Encoding::kCdr, b);
  b.resize(b.size() - 10);
  ros_msgs::Image out;
  try {
    ros_msgs::decode(b, Encoding::kCdr, out);
    FAIL() << "no error";
  } catch (const ros_msgs::DecodeError& e) {
    EXPECT_NE(std::string(e.what()).find("sensor_msgs/msg/Image"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'data'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("at byte"), std::string::npos) << e.what();
  }
}

TEST(RosMsgs, WrongTypeOrEncapsulationIsAnError) {
  std::vector<std::uint8_t> b;
  ros_msgs::encode(test::sample_pose(0), Encoding::kCdr, b);
  ros_msgs::Imu imu;
  EXPECT_THROW(ros_msgs::decode(b, Encoding::kCdr, imu), ros_msgs::DecodeError);
  b[1] = 0x00;  // CDR big-endian: not supported
  ros_msgs::PoseStamped pose;
  EXPECT_THROW(ros_msgs::decode(b, Encoding::kCdr, pose), ros_msgs::DecodeError);
  ros_msgs::encode(test::sample_imu(0), Encoding::kRos1, b);
  b.push_back(0);  // ROS 1 allows no trailing bytes
  EXPECT_THROW(ros_msgs::decode(b, Encoding::kRos1, imu), ros_msgs::DecodeError);
}

TEST(RosMsgs, RandomBytesNeverCrashTheDecoder) {
  std::uint32_t state = 12345;
  auto rnd = [&] { return state = state * 1664525u + 1013904223u; };
  std::vector<std::uint8_t> b;
  int errors = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    ros_msgs::encode(test::sample_camera_info(trial), Encoding::kCdr, b);
    for (int k = 0; k < 3; ++k) b[rnd() % b.size()] ^= static_cast<std::uint8_t>(1 + rnd() % 255);
    b.resize(b.size() - rnd() % 8);
    ros_msgs::CameraInfo out;
    try {
      ros_msgs::decode(b, trial % 2 ? Encoding::kCdr : Encoding::kRos1, out);
    } catch (const ros_msgs::DecodeError&) {
      ++errors;
    }
  }
  EXPECT_GT(errors, 0);
}

TEST(RosMsgs, TimeFromNanoseconds) {
  EXPECT_EQ(ros_msgs::Time::from_ns(1'500'000'001), (ros_msgs::Time{1, 500'000'001}));
  EXPECT_EQ(ros_msgs::Time::from_ns(-1), (ros_msgs::Time{-1, 999'999'999}));
  EXPECT_EQ(ros_msgs::Time::from_ns(123'456'789'012).to_ns(), 123'456'789'012);
}

}  // namespace
}  // namespace vigs::io
