// cyclone_pose_reader: an independent DDS implementation (Eclipse Cyclone DDS 0.10, Debian's
// cyclonedds-dev; types compiled by its own idlc from src/dds/idl) subscribing to VIGS's
// rt/vigs/pose, rt/vigs/odom, rt/tf and rt/vigs/pose_quality, as a ROS 2 node on
// rmw_cyclonedds would (with vigs_msgs built). It shares no
// code with the Fast DDS side except the expected pattern (tests/dds/pose_pattern.hpp).
// Loopback only: CYCLONEDDS_URI must be set (the test sets NetworkInterface 127.0.0.1, no
// multicast, peer 127.0.0.1); without it this program sets that configuration itself.
// Prints "ready" once its readers exist, then one JSON line per topic:
//   {"topic":..,"samples":N,"in_order":B,"pattern":B,"writer_type":"<type name announced>"}
// Exit 0 when every topic got `--count` samples in order matching the pattern and announced by
// a writer with the ROS 2 type name; 3 otherwise; 1 on a DDS error.
#include <dds/dds.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include "geometry_msgs.h"
#include "nav_msgs.h"
#include "pose_pattern.hpp"
#include "tf2_msgs.h"
#include "vigs_msgs.h"

namespace {

constexpr const char* kLoopbackUri =
    "<CycloneDDS><Domain id=\"any\"><General><Interfaces><NetworkInterface address=\"127.0.0.1\"/>"
    "</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery><Peers>"
    "<Peer address=\"127.0.0.1\"/></Peers><ParticipantIndex>auto</ParticipantIndex>"
    "<MaxAutoParticipantIndex>32</MaxAutoParticipantIndex></Discovery></Domain></CycloneDDS>";

struct TopicCheck {
  const char* topic = "";
  const char* expected_type = "";
  dds_entity_t reader = 0;
  int samples = 0;
  bool in_order = true;
  bool pattern = true;
  std::int64_t last_index = -1;
  std::string writer_type;
};

std::int64_t stamp_ns(const builtin_interfaces_msg_dds__Time_& t) {
  return static_cast<std::int64_t>(t.sec) * 1'000'000'000 + static_cast<std::int64_t>(t.nanosec);
}

// Checks one sample's stamp against the pattern; returns the pattern index (or -1).
std::int64_t check_stamp(TopicCheck& c, const std_msgs_msg_dds__Header_& h, const char* frame) {
  const std::int64_t i = vigs::dds::test::pattern_index(stamp_ns(h.stamp));
  if (i < 0 || i <= c.last_index) c.in_order = false;
  if (i < 0 || h.frame_id == nullptr || std::strcmp(h.frame_id, frame) != 0) c.pattern = false;
  c.last_index = i;
  ++c.samples;
  return i;
}

void check_pose(TopicCheck& c, const geometry_msgs_msg_dds__PoseWithCovariance_& p,
                std::int64_t i) {
  if (i < 0) return;
  const vigs::PoseSample s = vigs::dds::test::pattern_sample(static_cast<std::uint64_t>(i));
  for (int k = 0; k < 36; ++k) {
    if (p.covariance[k] != s.covariance[k]) c.pattern = false;
  }
  if (p.pose.position.x != s.p_w_m[0] || p.pose.position.y != s.p_w_m[1] ||
      p.pose.orientation.z != s.q_w_xyzw[2] || p.pose.orientation.w != s.q_w_xyzw[3]) {
    c.pattern = false;
  }
}

template <class Msg, class Fn>
void take_all(TopicCheck& c, Fn&& check) {
  void* samples[16] = {};
  dds_sample_info_t infos[16];
  for (;;) {
    const dds_return_t n = dds_take(c.reader, samples, infos, 16, 16);
    if (n <= 0) return;
    for (dds_return_t k = 0; k < n; ++k) {
      if (infos[k].valid_data) check(*static_cast<const Msg*>(samples[k]));
    }
    dds_return_loan(c.reader, samples, n);
  }
}

// Type names announced by remote writers on our topics (the DCPSPublication builtin topic).
void read_publications(dds_entity_t builtin, TopicCheck* checks, int n) {
  void* samples[16] = {};
  dds_sample_info_t infos[16];
  for (;;) {
    const dds_return_t got = dds_take(builtin, samples, infos, 16, 16);
    if (got <= 0) return;
    for (dds_return_t k = 0; k < got; ++k) {
      if (!infos[k].valid_data) continue;
      const auto* ep = static_cast<const dds_builtintopic_endpoint_t*>(samples[k]);
      for (int t = 0; t < n; ++t) {
        if (std::strcmp(ep->topic_name, checks[t].topic) == 0)
          checks[t].writer_type = ep->type_name;
      }
    }
    dds_return_loan(builtin, samples, got);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int domain = 0, count = 100, timeout_s = 60;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const int v = std::atoi(argv[i + 1]);
    if (k == "--domain")
      domain = v;
    else if (k == "--count")
      count = v;
    else if (k == "--timeout-s")
      timeout_s = v;
    else {
      std::fprintf(stderr, "cyclone_pose_reader: unknown option %s\n", k.c_str());
      return 64;
    }
  }
  if (std::getenv("CYCLONEDDS_URI") == nullptr) setenv("CYCLONEDDS_URI", kLoopbackUri, 1);

  const dds_entity_t participant =
      dds_create_participant(static_cast<dds_domainid_t>(domain), nullptr, nullptr);
  if (participant < 0) {
    std::fprintf(stderr, "cyclone: create_participant: %s\n", dds_strretcode(-participant));
    return 1;
  }
  constexpr int kTopics = 4;
  TopicCheck checks[kTopics];
  checks[0].topic = "rt/vigs/pose";
  checks[0].expected_type = "geometry_msgs::msg::dds_::PoseWithCovarianceStamped_";
  checks[1].topic = "rt/vigs/odom";
  checks[1].expected_type = "nav_msgs::msg::dds_::Odometry_";
  checks[2].topic = "rt/tf";
  checks[2].expected_type = "tf2_msgs::msg::dds_::TFMessage_";
  checks[3].topic = "rt/vigs/pose_quality";
  checks[3].expected_type = "vigs_msgs::msg::dds_::PoseQuality_";
  const dds_topic_descriptor_t* descs[kTopics] = {
      &geometry_msgs_msg_dds__PoseWithCovarianceStamped__desc, &nav_msgs_msg_dds__Odometry__desc,
      &tf2_msgs_msg_dds__TFMessage__desc, &vigs_msgs_msg_dds__PoseQuality__desc};
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
  dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos, DDS_HISTORY_KEEP_ALL, 0);
  for (int t = 0; t < kTopics; ++t) {
    const dds_entity_t topic =
        dds_create_topic(participant, descs[t], checks[t].topic, nullptr, nullptr);
    if (topic < 0) {
      std::fprintf(stderr, "cyclone: create_topic %s: %s\n", checks[t].topic,
                   dds_strretcode(-topic));
      return 1;
    }
    checks[t].reader = dds_create_reader(participant, topic, qos, nullptr);
    if (checks[t].reader < 0) {
      std::fprintf(stderr, "cyclone: create_reader: %s\n", dds_strretcode(-checks[t].reader));
      return 1;
    }
  }
  dds_delete_qos(qos);
  const dds_entity_t publications =
      dds_create_reader(participant, DDS_BUILTIN_TOPIC_DCPSPUBLICATION, nullptr, nullptr);
  std::printf("ready\n");
  std::fflush(stdout);

  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
  auto done = [&] {
    for (const TopicCheck& c : checks) {
      if (c.samples < count || c.writer_type.empty()) return false;
    }
    return true;
  };
  while (!done() && std::chrono::steady_clock::now() < deadline) {
    take_all<geometry_msgs_msg_dds__PoseWithCovarianceStamped_>(checks[0], [&](const auto& m) {
      check_pose(checks[0], m.pose, check_stamp(checks[0], m.header, "map"));
    });
    take_all<nav_msgs_msg_dds__Odometry_>(checks[1], [&](const auto& m) {
      const std::int64_t i = check_stamp(checks[1], m.header, "map");
      check_pose(checks[1], m.pose, i);
      if (m.child_frame_id == nullptr || std::strcmp(m.child_frame_id, "camera") != 0 ||
          m.twist.twist.angular.z != 0.2) {
        checks[1].pattern = false;
      }
    });
    take_all<tf2_msgs_msg_dds__TFMessage_>(checks[2], [&](const auto& m) {
      if (m.transforms._length != 1) {
        checks[2].pattern = false;
        ++checks[2].samples;
        return;
      }
      const auto& t = m.transforms._buffer[0];
      const std::int64_t i = check_stamp(checks[2], t.header, "map");
      if (t.child_frame_id == nullptr || std::strcmp(t.child_frame_id, "camera") != 0) {
        checks[2].pattern = false;
      }
      if (i >= 0 && t.transform.translation.y !=
                        vigs::dds::test::pattern_sample(static_cast<std::uint64_t>(i)).p_w_m[1]) {
        checks[2].pattern = false;
      }
    });
    take_all<vigs_msgs_msg_dds__PoseQuality_>(checks[3], [&](const auto& m) {
      const std::int64_t i = check_stamp(checks[3], m.header, "map");
      if (i < 0) return;
      const vigs::PoseSample s = vigs::dds::test::pattern_sample(static_cast<std::uint64_t>(i));
      if (m.frame_index != s.frame_index || m.source != static_cast<std::uint8_t>(s.source) ||
          m.flags != s.flags || m.keyframe != s.keyframe) {
        checks[3].pattern = false;
      }
    });
    if (publications > 0) read_publications(publications, checks, kTopics);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  bool ok = true;
  for (const TopicCheck& c : checks) {
    const bool type_ok = c.writer_type == c.expected_type;
    ok = ok && c.samples == count && c.in_order && c.pattern && type_ok;
    std::printf(
        "{\"topic\":\"%s\",\"samples\":%d,\"in_order\":%s,\"pattern\":%s,\"writer_type\":\"%s\"}\n",
        c.topic, c.samples, c.in_order ? "true" : "false", c.pattern ? "true" : "false",
        c.writer_type.c_str());
  }
  std::fflush(stdout);
  dds_delete(participant);
  return ok ? 0 : 3;
}
