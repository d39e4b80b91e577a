#pragma once
// DdsConfig: the `dds:` config section checked and resolved for the DDS roles. Everything a
// participant needs comes from here: domain, interface whitelist, shared memory, discovery
// peers, topic names, frame ids, and the QoS profiles XML (read here, loaded into Fast DDS by
// the roles). Every check that fails names the config key or the file.
#include <stdexcept>
#include <string>
#include <vector>

#include "core/config/dds_settings.hpp"
#include "dds/topic_names.hpp"

namespace vigs::dds {

/// A bad `dds:` setting or QoS file. what() names the key (dds.xxx) or the file (and line).
class DdsConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Highest domain id the RTPS default port mapping allows (7400 + 250 * id + 11 <= 65535).
inline constexpr int kMaxDomainId = 232;

struct DdsConfig {
  bool enabled = true;
  int domain_id = 0;
  std::string interface_ip = "127.0.0.1";  ///< the only interface UDP may use
  bool loopback_only = true;               ///< interface_ip is a 127.x address
  bool shared_memory = true;
  /// Fast DDS's shared-memory healthy-check timeout: a writer that (re)opens the port of a reader
  /// whose process is stopped waits this long in write() before declaring it dead.
  int shm_peer_check_ms = 1000;
  /// Unicast discovery peers. Loopback: 127.0.0.1 unless configured. Otherwise empty means
  /// multicast discovery (Fast DDS's default).
  std::vector<std::string> initial_peers;
  TopicNames topics = TopicNames::from_prefix("rt/vigs");
  std::string map_frame_id = "map";
  std::string camera_frame_id = "camera";
  std::string qos_source;  ///< the QoS file's path (or the built-in default's name), for messages
  std::string qos_xml;     ///< its text, checked: well-formed, every profile below present
  std::string pose_qos_profile = "vigs_pose_writer";
  std::string keyframe_qos_profile = "vigs_keyframe_writer";
  std::string status_qos_profile = "vigs_status_writer";
  std::string reader_qos_profile = "vigs_reader";
};

/// Checks `settings` and reads the QoS XML. A relative dds.qos_profiles is resolved against the
/// directory of `config_path`; an empty `config_path` means the built-in default configuration,
/// whose QoS file (firmware_config/dds/qos_profiles.xml) is compiled into the binary.
/// Throws DdsConfigError for: a domain id outside [0, 232]; an interface_ip or initial peer that
/// is not an IPv4 address; an interface_ip this machine does not have; an empty topic prefix or
/// frame id; a missing, unreadable or malformed QoS file (file:line); a profile key naming no
/// profile of the right kind in that file.
DdsConfig resolve_dds_config(const config::DdsSettings& settings, const std::string& config_path);

/// The same with the built-in configuration's settings and a domain override (tests, tools).
DdsConfig default_dds_config(int domain_id);

/// IPv4 addresses of this machine's interfaces (getifaddrs), for error messages and checks.
std::vector<std::string> local_ipv4_addresses();

/// The built-in QoS XML (firmware_config/dds/qos_profiles.xml at build time).
const std::string& builtin_qos_xml();
inline constexpr const char* kBuiltinQosName = "built-in firmware_config/dds/qos_profiles.xml";

}  // namespace vigs::dds
