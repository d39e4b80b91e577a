// `vigs echo` and `vigs topics` end to end, as separate processes: the real vigs binary against
// PosePublisher in dds_pose_source. JSON lines parse, every pose arrives in order with its stamp
// and covariance, no "nan"; all topics include pose_quality; topics lists the VIGS topics with
// their ROS 2 types; bad input is a clear error. Domains 160-163.
#include <gtest/gtest.h>

#include <chrono>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "dds/ros_time.hpp"
#include "pose_pattern.hpp"
#include "process.hpp"
#include "shm_janitor.hpp"

namespace vigs::dds {
namespace {

using namespace std::chrono_literals;
using nlohmann::json;

std::vector<json> json_lines(const std::string& text) {
  std::vector<json> out;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty()) out.push_back(json::parse(line));  // throws (fails) on a malformed line
  }
  return out;
}

TEST(VigsEcho, PrintsEveryPoseAsJsonInOrder) {
  test::ShmJanitor janitor;
  constexpr int kCount = 40;
  test::ChildProcess echo({VIGS_BINARY, "echo", "/vigs/pose", "--domain", "160", "--count",
                           std::to_string(kCount), "--timeout", "60"});
  test::ChildProcess source({VIGS_DDS_POSE_SOURCE, "--domain", "160", "--count",
                             std::to_string(kCount), "--rate-hz", "50", "--wait-s", "30",
                             "--wait-all", "0"});
  ASSERT_EQ(echo.wait(90s), 0) << echo.output();
  EXPECT_EQ(source.wait(60s), 0) << source.output();
  std::string values = echo.output();  // no nan/inf as a value ("nanosec" is a key)
  for (auto p = values.find("nanosec"); p != std::string::npos; p = values.find("nanosec")) {
    values.erase(p, 7);
  }
  for (const char* bad : {"nan", "NaN", "inf"}) EXPECT_EQ(values.find(bad), std::string::npos);
  const auto lines = json_lines(echo.output());
  ASSERT_EQ(lines.size(), static_cast<std::size_t>(kCount));
  for (int i = 0; i < kCount; ++i) {
    const json& l = lines[static_cast<std::size_t>(i)];
    const PoseSample s = test::pattern_sample(static_cast<std::uint64_t>(i));
    EXPECT_EQ(l["topic"], "rt/vigs/pose");
    EXPECT_EQ(l["type"], "geometry_msgs/msg/PoseWithCovarianceStamped");
    const json& h = l["msg"]["header"];
    EXPECT_EQ(
        to_ns(h["stamp"]["sec"].get<std::int32_t>(), h["stamp"]["nanosec"].get<std::uint32_t>()),
        s.t_ns);
    EXPECT_EQ(h["frame_id"], "map");
    const json& cov = l["msg"]["pose"]["covariance"];
    ASSERT_EQ(cov.size(), 36u);
    for (int k = 0; k < 36; ++k)
      EXPECT_EQ(cov[static_cast<std::size_t>(k)].get<double>(), s.covariance[k]);
    EXPECT_EQ(l["msg"]["pose"]["pose"]["position"]["y"].get<double>(), s.p_w_m[1]);
  }
}

TEST(VigsEcho, AllTopicsWithoutATopicArgument) {
  test::ShmJanitor janitor;
  test::ChildProcess echo(
      {VIGS_BINARY, "echo", "--domain", "161", "--count", "30", "--timeout", "60"});
  test::ChildProcess source({VIGS_DDS_POSE_SOURCE, "--domain", "161", "--count", "10", "--rate-hz",
                             "50", "--wait-s", "30"});
  ASSERT_EQ(echo.wait(90s), 0) << echo.output();
  source.wait(60s);
  std::map<std::string, int> per_topic;
  for (const json& l : json_lines(echo.output())) per_topic[l["topic"]]++;
  // 10 samples on each of pose, odom and tf: 30 lines, whatever the interleaving; keyframes and
  // status may come in between, so at least some of each pose topic are there.
  EXPECT_GT(per_topic["rt/vigs/pose"], 0);
  EXPECT_GT(per_topic["rt/vigs/odom"], 0);
  EXPECT_GT(per_topic["rt/tf"], 0);
  EXPECT_GT(per_topic["rt/vigs/pose_quality"], 0);
}

TEST(VigsTopics, ListsTheVigsTopicsWithRos2Types) {
  test::ShmJanitor janitor;
  test::ChildProcess source({VIGS_DDS_POSE_SOURCE, "--domain", "162", "--count", "1", "--wait-s",
                             "30"});  // waits for a subscriber that never comes
  test::ChildProcess topics({VIGS_BINARY, "topics", "--domain", "162", "--wait", "3", "--json"});
  ASSERT_EQ(topics.wait(60s), 0) << topics.output();
  std::map<std::string, std::string> types;
  for (const json& l : json_lines(topics.output())) {
    if (l["writers"].get<int>() > 0) types[l["topic"]] = l["type"];
  }
  EXPECT_EQ(types["rt/vigs/pose"], "geometry_msgs/msg/PoseWithCovarianceStamped");
  EXPECT_EQ(types["rt/vigs/odom"], "nav_msgs/msg/Odometry");
  EXPECT_EQ(types["rt/tf"], "tf2_msgs/msg/TFMessage");
  EXPECT_EQ(types["rt/vigs/keyframe"], "geometry_msgs/msg/PoseStamped");
  EXPECT_EQ(types["rt/vigs/status"], "vigs_msgs/msg/Status");
  EXPECT_EQ(types["rt/vigs/pose_quality"], "vigs_msgs/msg/PoseQuality");
}

TEST(VigsEcho, BadInputIsAClearError) {
  test::ChildProcess bad_domain({VIGS_BINARY, "echo", "--domain", "300", "--count", "1"}, {}, true);
  EXPECT_EQ(bad_domain.wait(30s), 1);
  EXPECT_NE(bad_domain.output().find("dds.domain_id"), std::string::npos) << bad_domain.output();
  test::ChildProcess no_writer(
      {VIGS_BINARY, "echo", "rt/not/there", "--domain", "163", "--timeout", "1"}, {}, true);
  EXPECT_EQ(no_writer.wait(30s), 1);
  EXPECT_NE(no_writer.output().find("no writer of topic rt/not/there"), std::string::npos)
      << no_writer.output();
}

}  // namespace
}  // namespace vigs::dds
