#include "dds/subscriber.hpp"

#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/subscriber/qos/DataReaderQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <stdexcept>
#include <thread>

#include "dds/participant.hpp"
#include "geometry_msgsPubSubTypes.h"
#include "nav_msgsPubSubTypes.h"
#include "tf2_msgsPubSubTypes.h"
#include "vigs_msgsPubSubTypes.h"

namespace vigs::dds {

namespace fdds = eprosima::fastdds::dds;

namespace {

template <class Msg>
struct PubSubTypeOf;
template <>
struct PubSubTypeOf<geometry_msgs::msg::dds_::PoseWithCovarianceStamped_> {
  using type = geometry_msgs::msg::dds_::PoseWithCovarianceStamped_PubSubType;
};
template <>
struct PubSubTypeOf<geometry_msgs::msg::dds_::PoseStamped_> {
  using type = geometry_msgs::msg::dds_::PoseStamped_PubSubType;
};
template <>
struct PubSubTypeOf<nav_msgs::msg::dds_::Odometry_> {
  using type = nav_msgs::msg::dds_::Odometry_PubSubType;
};
template <>
struct PubSubTypeOf<tf2_msgs::msg::dds_::TFMessage_> {
  using type = tf2_msgs::msg::dds_::TFMessage_PubSubType;
};
template <>
struct PubSubTypeOf<vigs_msgs::msg::dds_::Status_> {
  using type = vigs_msgs::msg::dds_::Status_PubSubType;
};
template <>
struct PubSubTypeOf<vigs_msgs::msg::dds_::PoseQuality_> {
  using type = vigs_msgs::msg::dds_::PoseQuality_PubSubType;
};

struct ReaderBase : fdds::DataReaderListener {
  std::string topic;
  fdds::DataReader* reader = nullptr;
};

template <class Msg>
struct TypedReader final : ReaderBase {
  std::function<void(const Msg&)> on_sample;
  Msg msg;
  void on_data_available(fdds::DataReader* r) override {
    fdds::SampleInfo info;
    while (r->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) on_sample(msg);
    }
  }
};

}  // namespace

struct Subscriber::Impl {
  Impl(const DdsConfig& c, const std::string& name) : config(c), participant(c, name) {
    subscriber = participant->create_subscriber(fdds::SUBSCRIBER_QOS_DEFAULT);
    if (subscriber == nullptr) throw std::runtime_error("Fast DDS: cannot create the subscriber");
    if (subscriber->get_datareader_qos_from_profile(c.reader_qos_profile, reader_qos) !=
        ReturnCode_t::RETCODE_OK) {
      throw DdsConfigError("dds.reader_qos_profile: Fast DDS has no data_reader profile '" +
                           c.reader_qos_profile + "' (from " + c.qos_source + ")");
    }
  }
  ~Impl() {
    // Readers first (their listeners are ours), then everything else with the participant.
    for (auto& r : readers) {
      r->reader->set_listener(nullptr);
      subscriber->delete_datareader(r->reader);
    }
  }

  DdsConfig config;
  Participant participant;
  fdds::Subscriber* subscriber = nullptr;
  fdds::DataReaderQos reader_qos;
  std::vector<fdds::TypeSupport> types;
  std::vector<std::unique_ptr<ReaderBase>> readers;
};

Subscriber::Subscriber(const DdsConfig& config, const std::string& participant_name)
    : impl_(std::make_unique<Impl>(config, participant_name)) {}

Subscriber::~Subscriber() = default;

template <class Msg>
void Subscriber::subscribe(const std::string& topic_name, std::function<void(const Msg&)> cb) {
  Impl& m = *impl_;
  fdds::TypeSupport type(new typename PubSubTypeOf<Msg>::type());
  if (type.register_type(m.participant.get()) != ReturnCode_t::RETCODE_OK) {
    throw std::runtime_error("Fast DDS: cannot register type " + type.get_type_name());
  }
  fdds::Topic* topic =
      m.participant->create_topic(topic_name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
  if (topic == nullptr) {
    throw std::runtime_error("Fast DDS: cannot create topic " + topic_name + " of type " +
                             type.get_type_name() + " (already subscribed with another type?)");
  }
  auto r = std::make_unique<TypedReader<Msg>>();
  r->topic = topic_name;
  r->on_sample = std::move(cb);
  r->reader = m.subscriber->create_datareader(topic, m.reader_qos, r.get(),
                                              fdds::StatusMask::data_available());
  if (r->reader == nullptr)
    throw std::runtime_error("Fast DDS: cannot create reader " + topic_name);
  m.types.push_back(type);
  m.readers.push_back(std::move(r));
}

int Subscriber::matched_writers(const std::string& topic) const {
  for (const auto& r : impl_->readers) {
    if (r->topic != topic) continue;
    fdds::SubscriptionMatchedStatus st;
    r->reader->get_subscription_matched_status(st);
    return st.current_count;
  }
  return 0;
}

bool Subscriber::wait_for_writers(int n, std::chrono::milliseconds timeout) const {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    bool all = true;
    for (const auto& r : impl_->readers) {
      fdds::SubscriptionMatchedStatus st;
      r->reader->get_subscription_matched_status(st);
      all = all && st.current_count >= n;
    }
    if (all) return true;
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

template void Subscriber::subscribe(
    const std::string&,
    std::function<void(const geometry_msgs::msg::dds_::PoseWithCovarianceStamped_&)>);
template void Subscriber::subscribe(
    const std::string&, std::function<void(const geometry_msgs::msg::dds_::PoseStamped_&)>);
template void Subscriber::subscribe(const std::string&,
                                    std::function<void(const nav_msgs::msg::dds_::Odometry_&)>);
template void Subscriber::subscribe(const std::string&,
                                    std::function<void(const tf2_msgs::msg::dds_::TFMessage_&)>);
template void Subscriber::subscribe(const std::string&,
                                    std::function<void(const vigs_msgs::msg::dds_::Status_&)>);
template void Subscriber::subscribe(const std::string&,
                                    std::function<void(const vigs_msgs::msg::dds_::PoseQuality_&)>);

}  // namespace vigs::dds
