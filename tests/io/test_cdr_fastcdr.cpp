// The codecs' CDR archive (archive.hpp) against eProsima Fast CDR (libfastcdr, the CDR library
// Fast DDS uses), driven by the same field order (visit_fields.hpp): every message type gives
// byte-identical CDR both ways and each side decodes the other's bytes, so recordings and DDS
// samples share one CDR format. Fast CDR is not the production codec because it measured slower
// in bench_io (BENCHMARKS.md, "CDR: own archive vs Fast CDR").
#include <gtest/gtest.h>

#include <vector>

#include "io/ros_msgs/fastcdr_archive.hpp"
#include "io/ros_msgs/visit_fields.hpp"
#include "msg_samples.hpp"

namespace vigs::io {
namespace {

using ros_msgs::Encoding;

template <class Msg, class Visit>
std::vector<std::uint8_t> fastcdr_encode(const Msg& m, Visit visit) {
  ros_msgs::detail::SizeBound bound;
  visit(bound, m);
  std::vector<std::uint8_t> out(bound.bytes);
  ros_msgs::detail::FastCdrEncoder ar(out);
  visit(ar, m);
  ar.finish();
  return out;
}

template <class Msg, class Visit>
Msg fastcdr_decode(const std::vector<std::uint8_t>& bytes, Visit visit) {
  Msg m;
  ros_msgs::detail::FastCdrDecoder ar(bytes, ros_msgs::MessageTraits<Msg>::kRos2Name);
  visit(ar, m);
  ar.finish();
  return m;
}

template <class Msg, class Visit>
void expect_same_cdr(const Msg& m, Visit visit) {
  std::vector<std::uint8_t> ours;
  ros_msgs::encode(m, Encoding::kCdr, ours);
  const std::vector<std::uint8_t> theirs = fastcdr_encode(m, visit);
  EXPECT_EQ(ours, theirs) << ros_msgs::MessageTraits<Msg>::kRos2Name;
  Msg expected = m;
  if constexpr (requires { expected.header.seq; }) expected.header.seq = 0;  // ROS 1 only
  EXPECT_EQ(fastcdr_decode<Msg>(ours, visit), expected);
  Msg back;
  ros_msgs::decode(theirs, Encoding::kCdr, back);
  EXPECT_EQ(back, expected);
}

TEST(CdrFastCdr, EveryTypeIsByteIdenticalAndCrossDecodes) {
  using namespace ros_msgs::detail;
  for (int i = 0; i < 4; ++i) {
    expect_same_cdr(test::sample_image(i, false), VisitImage{});
    expect_same_cdr(test::sample_image(i, true), VisitImage{});
    expect_same_cdr(test::sample_imu(i), VisitImu{});
    auto c = test::sample_camera_info(i);
    expect_same_cdr(c, VisitCameraInfo{});
    c.d.clear();  // an empty sequence before an aligned array
    expect_same_cdr(c, VisitCameraInfo{});
    expect_same_cdr(test::sample_pose(i), VisitPoseStamped{});
    expect_same_cdr(test::sample_odometry(i), VisitOdometry{});
    expect_same_cdr(test::sample_serial(i), VisitSerialChunk{});
  }
}

TEST(CdrFastCdr, FastCdrDecoderRefusesTruncatedBytesNamingTheField) {
  std::vector<std::uint8_t> b;
  ros_msgs::encode(test::sample_image(1, false), Encoding::kCdr, b);
  b.resize(b.size() - 10);
  try {
    (void)fastcdr_decode<ros_msgs::Image>(b, ros_msgs::detail::VisitImage{});
    FAIL() << "no error";
  } catch (const ros_msgs::DecodeError& e) {
    EXPECT_NE(std::string(e.what()).find("'data'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("at byte"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vigs::io
