// Interoperability: our Fast DDS PosePublisher (process 1, dds_pose_source) to a subscriber on
// Eclipse Cyclone DDS (process 2, cyclone_pose_reader, its own idlc-generated types). Every
// sample of rt/vigs/pose, rt/vigs/odom, rt/tf and rt/vigs/pose_quality (VIGS's own type: source,
// flags, frame index, keyframe) arrives, in order, with the ROS 2 type name, frame ids and
// stamps. Both sides loopback only. The Cyclone reader starts first (a volatile
// reader joining late could miss the start). Domain 159.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "process.hpp"
#include "shm_janitor.hpp"

namespace vigs::dds {
namespace {

using namespace std::chrono_literals;

// Cyclone DDS 0.10 on loopback: the 127.0.0.1 interface only, no multicast (lo has none),
// unicast discovery to 127.0.0.1 over the first 32 participant indices.
constexpr const char* kCycloneLoopback =
    "CYCLONEDDS_URI=<CycloneDDS><Domain id=\"any\"><General><Interfaces>"
    "<NetworkInterface address=\"127.0.0.1\"/></Interfaces><AllowMulticast>false</AllowMulticast>"
    "</General><Discovery><Peers><Peer address=\"127.0.0.1\"/></Peers>"
    "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>32</MaxAutoParticipantIndex>"
    "</Discovery></Domain></CycloneDDS>";

TEST(DdsCycloneInterop, CycloneReceivesEveryPoseOdomTfAndPoseQualityInOrder) {
  test::ShmJanitor janitor;
  constexpr int kCount = 60;
  test::ChildProcess reader({VIGS_CYCLONE_POSE_READER, "--domain", "159", "--count",
                             std::to_string(kCount), "--timeout-s", "60"},
                            {kCycloneLoopback});
  for (int i = 0; i < 1000 && reader.output().find("ready") == std::string::npos; ++i) {
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_NE(reader.output().find("ready"), std::string::npos) << "Cyclone reader did not start";
  test::ChildProcess source({VIGS_DDS_POSE_SOURCE, "--domain", "159", "--count",
                             std::to_string(kCount), "--rate-hz", "50", "--wait-s", "30",
                             "--wait-quality", "1"});
  EXPECT_EQ(source.wait(90s), 0) << source.output();
  EXPECT_EQ(reader.wait(60s), 0) << reader.output();
  const std::string& out = reader.output();
  for (const char* line :
       {"{\"topic\":\"rt/vigs/pose\",\"samples\":60,\"in_order\":true,\"pattern\":true,"
        "\"writer_type\":\"geometry_msgs::msg::dds_::PoseWithCovarianceStamped_\"}",
        "{\"topic\":\"rt/vigs/odom\",\"samples\":60,\"in_order\":true,\"pattern\":true,"
        "\"writer_type\":\"nav_msgs::msg::dds_::Odometry_\"}",
        "{\"topic\":\"rt/tf\",\"samples\":60,\"in_order\":true,\"pattern\":true,"
        "\"writer_type\":\"tf2_msgs::msg::dds_::TFMessage_\"}",
        "{\"topic\":\"rt/vigs/pose_quality\",\"samples\":60,\"in_order\":true,"
        "\"pattern\":true,\"writer_type\":\"vigs_msgs::msg::dds_::PoseQuality_\"}"}) {
    EXPECT_NE(out.find(line), std::string::npos) << "missing " << line << "\nin:\n" << out;
  }
}

}  // namespace
}  // namespace vigs::dds
