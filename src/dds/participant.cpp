#include "dds/participant.hpp"

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastdds/rtps/transport/shared_mem/SharedMemTransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/log/Log.hpp>

#include <tinyxml2.h>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>

namespace vigs::dds {

namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;

namespace {

rtps::Locator_t udp_locator(const std::string& ip) {
  rtps::Locator_t loc;
  loc.kind = LOCATOR_KIND_UDPv4;
  rtps::IPLocator::setIPv4(loc, ip);
  loc.port = 0;  // 0: Fast DDS fills in the well-known port for the domain and participant
  return loc;
}

// profile name -> the source that defined it (profiles loaded in this process).
std::mutex g_profiles_mutex;
std::map<std::string, std::pair<std::string, std::string>> g_profiles;  // name -> {source, xml}

}  // namespace

fdds::DomainParticipantQos make_participant_qos(const DdsConfig& c, const std::string& name) {
  fdds::DomainParticipantQos q = fdds::PARTICIPANT_QOS_DEFAULT;
  q.name(name);
  q.transport().use_builtin_transports = false;
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.push_back(c.interface_ip);
  q.transport().user_transports.push_back(udp);
  if (c.shared_memory) {
    // A writer that opens (or, after its watchdog found it silent, reopens) a reader's port
    // runs a healthy check inside write(): with a stopped or hung reader process it waits the
    // whole timeout, 1 s by default -- the pose publisher thread stalls that long per port, and
    // the pose ring overflows at high rates (tests/dds/test_dds_never_blocks.cpp). A short
    // check bounds what a hung peer costs every other subscriber, but a reader that is alive
    // and merely loaded is then declared dead (duplicate deliveries were seen at 50 ms), so the
    // default stays Fast DDS's 1 s and the key is the robot's trade-off.
    auto shm = std::make_shared<eprosima::fastdds::rtps::SharedMemTransportDescriptor>();
    shm->healthy_check_timeout_ms(static_cast<std::uint32_t>(c.shm_peer_check_ms));
    q.transport().user_transports.push_back(shm);
  }
  auto& builtin = q.wire_protocol().builtin;
  for (const std::string& peer : c.initial_peers) {
    builtin.initialPeersList.push_back(udp_locator(peer));
  }
  if (c.loopback_only) {
    // An explicit metatraffic unicast locator and no multicast one: Fast DDS then announces
    // only 127.0.0.1 for discovery.
    builtin.metatrafficUnicastLocatorList.push_back(udp_locator(c.interface_ip));
  }
  return q;
}

void load_qos_profiles(const DdsConfig& c) {
  std::lock_guard lock(g_profiles_mutex);
  tinyxml2::XMLDocument doc;
  doc.Parse(c.qos_xml.data(), c.qos_xml.size());  // well-formed: checked by resolve_dds_config
  std::vector<std::string> names;
  if (const auto* root = doc.RootElement()) {
    const auto* profiles =
        std::string(root->Name()) == "profiles" ? root : root->FirstChildElement("profiles");
    for (const auto* e = profiles ? profiles->FirstChildElement() : nullptr; e != nullptr;
         e = e->NextSiblingElement()) {
      if (const char* n = e->Attribute("profile_name")) names.emplace_back(n);
    }
  }
  bool all_loaded = !names.empty();
  for (const std::string& n : names) {
    const auto it = g_profiles.find(n);
    if (it == g_profiles.end()) {
      all_loaded = false;
    } else if (it->second.second != c.qos_xml) {
      throw DdsConfigError(c.qos_source + ": QoS profile '" + n + "' is already loaded from " +
                           it->second.first +
                           " with other content (Fast DDS keeps one profile table per process)");
    }
  }
  if (all_loaded) return;
  if (fdds::DomainParticipantFactory::get_instance()->load_XML_profiles_string(
          c.qos_xml.data(), c.qos_xml.size()) != ReturnCode_t::RETCODE_OK) {
    throw DdsConfigError(c.qos_source +
                         ": Fast DDS rejected the QoS profiles (its XML parser's error is above)");
  }
  for (const std::string& n : names) g_profiles.emplace(n, std::make_pair(c.qos_source, c.qos_xml));
}

Participant::Participant(const DdsConfig& c, const std::string& name,
                         fdds::DomainParticipantListener* listener, const fdds::StatusMask& mask) {
  load_qos_profiles(c);
  p_ = fdds::DomainParticipantFactory::get_instance()->create_participant(
      c.domain_id, make_participant_qos(c, name), listener, mask);
  if (p_ == nullptr) {
    throw std::runtime_error("Fast DDS could not create participant '" + name + "' on domain " +
                             std::to_string(c.domain_id) + " (interface " + c.interface_ip + ")");
  }
}

Participant::~Participant() {
  if (p_ == nullptr) return;
  p_->set_listener(nullptr);
  p_->delete_contained_entities();
  fdds::DomainParticipantFactory::get_instance()->delete_participant(p_);
}

}  // namespace vigs::dds
