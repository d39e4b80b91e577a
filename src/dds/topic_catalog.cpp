#include "dds/topic_catalog.hpp"

#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <tuple>

#include "dds/participant.hpp"

namespace vigs::dds {

namespace fdds = eprosima::fastdds::dds;
namespace rtps = eprosima::fastrtps::rtps;

struct TopicCatalog::Impl : fdds::DomainParticipantListener {
  explicit Impl(const DdsConfig& c) : participant(c, "vigs_topics", this) {}
  ~Impl() override { participant->set_listener(nullptr); }

  void on_publisher_discovery(fdds::DomainParticipant*, rtps::WriterDiscoveryInfo&& info) override {
    const bool add = info.status == rtps::WriterDiscoveryInfo::DISCOVERED_WRITER;
    const bool remove = info.status == rtps::WriterDiscoveryInfo::REMOVED_WRITER;
    count(info.info.topicName().to_string(), info.info.typeName().to_string(), add, remove, true);
  }
  void on_subscriber_discovery(fdds::DomainParticipant*,
                               rtps::ReaderDiscoveryInfo&& info) override {
    const bool add = info.status == rtps::ReaderDiscoveryInfo::DISCOVERED_READER;
    const bool remove = info.status == rtps::ReaderDiscoveryInfo::REMOVED_READER;
    count(info.info.topicName().to_string(), info.info.typeName().to_string(), add, remove, false);
  }

  void count(const std::string& topic, const std::string& type, bool add, bool remove,
             bool writer) {
    if (!add && !remove) return;
    std::lock_guard l(mutex);
    DiscoveredTopic& t = seen[{topic, type}];
    t.name = topic;
    t.type = type;
    int& n = writer ? t.writers : t.readers;
    n += add ? 1 : (n > 0 ? -1 : 0);
  }

  mutable std::mutex mutex;
  std::map<std::pair<std::string, std::string>, DiscoveredTopic> seen;
  Participant participant;  // last: created after the table it fills, destroyed first
};

TopicCatalog::TopicCatalog(const DdsConfig& config) : impl_(std::make_unique<Impl>(config)) {}
TopicCatalog::~TopicCatalog() = default;

std::vector<DiscoveredTopic> TopicCatalog::topics() const {
  std::lock_guard l(impl_->mutex);
  std::vector<DiscoveredTopic> out;
  for (const auto& [key, t] : impl_->seen) out.push_back(t);
  return out;
}

std::string ros_type_name(const std::string& dds_type) {
  // pkg::msg::dds_::Name_ -> pkg/msg/Name
  const std::string mid = "::msg::dds_::";
  const auto p = dds_type.find(mid);
  if (p == std::string::npos || dds_type.empty() || dds_type.back() != '_') return dds_type;
  return dds_type.substr(0, p) + "/msg/" +
         dds_type.substr(p + mid.size(), dds_type.size() - p - mid.size() - 1);
}

}  // namespace vigs::dds
