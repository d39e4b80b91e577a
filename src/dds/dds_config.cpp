#include "dds/dds_config.hpp"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <netinet/in.h>
#include <tinyxml2.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "core/config/default_config.hpp"
#include "core/config/yaml_loader.hpp"

namespace vigs::dds {
namespace {

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out.empty() ? "none" : out;
}

bool is_ipv4(const std::string& s) {
  in_addr a{};
  return inet_pton(AF_INET, s.c_str(), &a) == 1;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// Profile names of one kind (<data_writer>/<data_reader>) under <dds><profiles> or <profiles>.
struct XmlProfiles {
  std::vector<std::string> writers;
  std::vector<std::string> readers;
};

XmlProfiles parse_profiles(const std::string& xml, const std::string& source) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS) {
    throw DdsConfigError(source + ":" + std::to_string(doc.ErrorLineNum()) +
                         ": malformed QoS XML: " + doc.ErrorStr() + " (dds.qos_profiles)");
  }
  const tinyxml2::XMLElement* root = doc.RootElement();
  const tinyxml2::XMLElement* profiles = nullptr;
  if (root != nullptr && std::strcmp(root->Name(), "profiles") == 0) profiles = root;
  if (root != nullptr && std::strcmp(root->Name(), "dds") == 0) {
    profiles = root->FirstChildElement("profiles");
  }
  if (profiles == nullptr) {
    throw DdsConfigError(source + ":" + std::to_string(root ? root->GetLineNum() : 1) +
                         ": not a Fast DDS profiles file (no <dds><profiles> element)");
  }
  XmlProfiles out;
  for (const tinyxml2::XMLElement* e = profiles->FirstChildElement(); e != nullptr;
       e = e->NextSiblingElement()) {
    const char* name = e->Attribute("profile_name");
    if (name == nullptr) continue;
    if (std::strcmp(e->Name(), "data_writer") == 0 || std::strcmp(e->Name(), "publisher") == 0) {
      out.writers.emplace_back(name);
    } else if (std::strcmp(e->Name(), "data_reader") == 0 ||
               std::strcmp(e->Name(), "subscriber") == 0) {
      out.readers.emplace_back(name);
    }
  }
  return out;
}

void require_profile(const std::vector<std::string>& have, const std::string& name,
                     const char* kind, const char* key, const std::string& source) {
  if (std::find(have.begin(), have.end(), name) != have.end()) return;
  throw DdsConfigError(std::string("dds.") + key + ": no <" + kind + "> profile '" + name +
                       "' in " + source + " (it has: " + join(have) + ")");
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw DdsConfigError("cannot read QoS profiles file " + path +
                         " (dds.qos_profiles): " + std::strerror(errno));
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

std::vector<std::string> local_ipv4_addresses() {
  std::vector<std::string> out;
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) return out;
  for (const ifaddrs* i = list; i != nullptr; i = i->ifa_next) {
    if (i->ifa_addr == nullptr || i->ifa_addr->sa_family != AF_INET) continue;
    char buf[INET_ADDRSTRLEN] = {};
    const auto* sin = reinterpret_cast<const sockaddr_in*>(i->ifa_addr);
    if (inet_ntop(AF_INET, &sin->sin_addr, buf, sizeof buf) != nullptr) out.emplace_back(buf);
  }
  freeifaddrs(list);
  return out;
}

DdsConfig resolve_dds_config(const config::DdsSettings& s, const std::string& config_path) {
  DdsConfig c;
  c.enabled = s.enabled;
  if (s.domain_id < 0 || s.domain_id > kMaxDomainId) {
    throw DdsConfigError("dds.domain_id: " + std::to_string(s.domain_id) + " is out of range [0, " +
                         std::to_string(kMaxDomainId) + "]");
  }
  c.domain_id = s.domain_id;

  if (!is_ipv4(s.interface_ip)) {
    throw DdsConfigError("dds.interface_ip: '" + s.interface_ip + "' is not an IPv4 address");
  }
  const std::vector<std::string> local = local_ipv4_addresses();
  if (std::find(local.begin(), local.end(), s.interface_ip) == local.end()) {
    throw DdsConfigError("dds.interface_ip: " + s.interface_ip +
                         " is not an address of this machine (it has: " + join(local) + ")");
  }
  c.interface_ip = s.interface_ip;
  c.loopback_only = s.interface_ip.rfind("127.", 0) == 0;
  c.shared_memory = s.shared_memory;
  c.shm_peer_check_ms = s.shm_peer_check_ms;

  std::stringstream peers(s.initial_peers);
  for (std::string item; std::getline(peers, item, ',');) {
    item = trim(item);
    if (item.empty()) continue;
    if (!is_ipv4(item)) {
      throw DdsConfigError("dds.initial_peers: '" + item + "' is not an IPv4 address");
    }
    c.initial_peers.push_back(item);
  }
  if (c.initial_peers.empty() && c.loopback_only) c.initial_peers.push_back(c.interface_ip);

  if (s.topic_prefix.empty() || s.topic_prefix.back() == '/' ||
      s.topic_prefix.find_first_of(" \t") != std::string::npos) {
    throw DdsConfigError("dds.topic_prefix: '" + s.topic_prefix +
                         "' must be a non-empty topic path without spaces or a trailing '/'");
  }
  c.topics = TopicNames::from_prefix(s.topic_prefix);
  if (s.map_frame_id.empty()) throw DdsConfigError("dds.map_frame_id: must not be empty");
  if (s.camera_frame_id.empty()) throw DdsConfigError("dds.camera_frame_id: must not be empty");
  if (s.camera_frame_id == s.map_frame_id) {
    throw DdsConfigError("dds.camera_frame_id: must differ from dds.map_frame_id");
  }
  c.map_frame_id = s.map_frame_id;
  c.camera_frame_id = s.camera_frame_id;

  // The QoS file: relative to the config file's directory; the built-in configuration's default
  // file is compiled in, so it works from any working directory.
  const std::filesystem::path qos(s.qos_profiles);
  if (s.qos_profiles.empty()) throw DdsConfigError("dds.qos_profiles: must name a file");
  if (config_path.empty() && qos.is_relative() &&
      s.qos_profiles == config::DdsSettings{}.qos_profiles) {
    c.qos_source = kBuiltinQosName;
    c.qos_xml = builtin_qos_xml();
  } else {
    const std::filesystem::path base = config_path.empty()
                                           ? std::filesystem::current_path()
                                           : std::filesystem::path(config_path).parent_path();
    c.qos_source = (qos.is_absolute() ? qos : (base / qos).lexically_normal()).string();
    c.qos_xml = read_file(c.qos_source);
  }
  const XmlProfiles profiles = parse_profiles(c.qos_xml, c.qos_source);
  require_profile(profiles.writers, s.pose_qos_profile, "data_writer", "pose_qos_profile",
                  c.qos_source);
  require_profile(profiles.writers, s.keyframe_qos_profile, "data_writer", "keyframe_qos_profile",
                  c.qos_source);
  require_profile(profiles.writers, s.status_qos_profile, "data_writer", "status_qos_profile",
                  c.qos_source);
  require_profile(profiles.readers, s.reader_qos_profile, "data_reader", "reader_qos_profile",
                  c.qos_source);
  c.pose_qos_profile = s.pose_qos_profile;
  c.keyframe_qos_profile = s.keyframe_qos_profile;
  c.status_qos_profile = s.status_qos_profile;
  c.reader_qos_profile = s.reader_qos_profile;
  return c;
}

DdsConfig default_dds_config(int domain_id) {
  config::DdsSettings s = config::load_config_text(config::default_config_text(),
                                                   std::string(config::kDefaultConfigName))
                              .dds;
  s.domain_id = domain_id;
  return resolve_dds_config(s, "");
}

}  // namespace vigs::dds
