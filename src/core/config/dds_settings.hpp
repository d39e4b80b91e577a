#pragma once
#include <string>

#include "core/config/visitor.hpp"

namespace vigs::config {

/// DDS output. The default keeps every participant on this machine: UDP restricted to the
/// loopback interface plus shared memory. A live robot names its network interface here.
struct DdsSettings {
  bool enabled = true;
  int domain_id = 0;
  std::string interface_ip = "127.0.0.1";  ///< UDP interface whitelist
  bool shared_memory = true;
  int shm_peer_check_ms = 1000;  ///< longest a write may wait on a silent shared-memory reader
  std::string topic_prefix = "rt/vigs";
  std::string qos_profiles = "../dds/qos_profiles.xml";
  std::string initial_peers;  ///< empty: 127.0.0.1 on loopback, multicast discovery otherwise
  std::string map_frame_id = "map";
  std::string camera_frame_id = "camera";
  std::string pose_qos_profile = "vigs_pose_writer";
  std::string keyframe_qos_profile = "vigs_keyframe_writer";
  std::string status_qos_profile = "vigs_status_writer";
  std::string reader_qos_profile = "vigs_reader";

  void visit(Visitor& v) {
    v.field("enabled", enabled, "publish poses and status on DDS");
    v.field("domain_id", domain_id, {"-", 0, 232, "DDS domain id"});
    v.field("interface_ip", interface_ip, {},
            "IPv4 address of the only interface UDP may use (127.0.0.1 = loopback only)");
    v.field("shared_memory", shared_memory, "also enable the shared-memory transport");
    v.field("shm_peer_check_ms", shm_peer_check_ms,
            {"ms", 5, 1000,
             "shared memory: how long a write waits for a silent reader's port to answer before "
             "it is declared dead (Fast DDS's healthy-check timeout; a hung peer stalls the "
             "publisher this long per port)"});
    v.field("topic_prefix", topic_prefix, {}, "ROS 2 style topic prefix");
    v.field("qos_profiles", qos_profiles, {}, "Fast DDS QoS XML, relative to this config file");
    v.field("initial_peers", initial_peers, {},
            "comma-separated IPv4 discovery peers (empty: 127.0.0.1 on loopback, else multicast)");
    v.field("map_frame_id", map_frame_id, {}, "world frame of poses, odometry and TF");
    v.field("camera_frame_id", camera_frame_id, {}, "camera frame: TF child, odometry child");
    v.field("pose_qos_profile", pose_qos_profile, {}, "writer profile: pose, odom, tf");
    v.field("keyframe_qos_profile", keyframe_qos_profile, {}, "writer profile: keyframe");
    v.field("status_qos_profile", status_qos_profile, {}, "writer profile: status");
    v.field("reader_qos_profile", reader_qos_profile, {}, "reader profile of vigs echo/tools");
    v.require(!interface_ip.empty(), "interface_ip", "must name an interface address");
  }
};

}  // namespace vigs::config
