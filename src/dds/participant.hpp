#pragma once
// Participant: one Fast DDS DomainParticipant configured from a DdsConfig, owned (RAII), as the
// publisher and subscriber roles need it.
//
// Transports (the loopback-only default is what keeps tests and the demo on this machine):
//  - builtin transports off; one UDPv4 transport whose interfaceWhiteList is dds.interface_ip;
//    plus shared memory when dds.shared_memory (same-host Fast DDS peers then use it for data);
//  - on loopback (lo has no multicast here): metatraffic unicast on 127.0.0.1 and 127.0.0.1 in
//    initialPeersList, so a Cyclone DDS reader finds the participant at once (without them it
//    did so only about 8 s late); no multicast locator is announced at all;
//  - another interface: Fast DDS's multicast discovery on it, plus dds.initial_peers if given.
// The QoS profiles XML is loaded into Fast DDS (a process-wide table) before the participant is
// created; writers and readers are then created from the named profiles.
#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>
#include <string>

#include "dds/dds_config.hpp"

namespace vigs::dds {

/// The participant QoS for `config` (transports, discovery peers, locators, name).
eprosima::fastdds::dds::DomainParticipantQos make_participant_qos(const DdsConfig& config,
                                                                  const std::string& name);

/// Loads config.qos_xml into Fast DDS. Fast DDS keeps profiles per process, so the same XML is
/// loaded once; a different XML that redefines an already loaded profile name is an error
/// (DdsConfigError naming both sources), as is an XML Fast DDS rejects.
void load_qos_profiles(const DdsConfig& config);

class Participant {
 public:
  /// Throws DdsConfigError when the QoS cannot be loaded, std::runtime_error when Fast DDS
  /// refuses the participant.
  Participant(
      const DdsConfig& config, const std::string& name,
      eprosima::fastdds::dds::DomainParticipantListener* listener = nullptr,
      const eprosima::fastdds::dds::StatusMask& mask = eprosima::fastdds::dds::StatusMask::none());
  ~Participant();
  Participant(const Participant&) = delete;
  Participant& operator=(const Participant&) = delete;

  [[nodiscard]] eprosima::fastdds::dds::DomainParticipant* get() const noexcept { return p_; }
  eprosima::fastdds::dds::DomainParticipant* operator->() const noexcept { return p_; }

 private:
  eprosima::fastdds::dds::DomainParticipant* p_ = nullptr;
};

}  // namespace vigs::dds
