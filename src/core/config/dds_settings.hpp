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
  std::string topic_prefix = "rt/vigs";
  std::string qos_profiles = "firmware_config/dds/qos_profiles.xml";

  void visit(Visitor& v) {
    v.field("enabled", enabled, "publish poses and status on DDS");
    v.field("domain_id", domain_id, {"-", 0, 232, "DDS domain id"});
    v.field("interface_ip", interface_ip, {},
            "IPv4 address of the only interface UDP may use (127.0.0.1 = loopback only)");
    v.field("shared_memory", shared_memory, "also enable the shared-memory transport");
    v.field("topic_prefix", topic_prefix, {}, "ROS 2 style topic prefix");
    v.field("qos_profiles", qos_profiles, {}, "QoS XML, relative to the project root");
    v.require(!interface_ip.empty(), "interface_ip", "must name an interface address");
  }
};

}  // namespace vigs::config
