#include "dds/pose_publisher.hpp"

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/publisher/qos/DataWriterQos.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>
#include <stdexcept>
#include <thread>

#include "dds/participant.hpp"
#include "dds/pose_messages.hpp"
#include "dds/status_message.hpp"
#include "geometry_msgsPubSubTypes.h"
#include "nav_msgsPubSubTypes.h"
#include "rt/clock.hpp"
#include "rt/thread_table.hpp"
#include "tf2_msgsPubSubTypes.h"
#include "vigs_msgsPubSubTypes.h"

namespace vigs::dds {

namespace fdds = eprosima::fastdds::dds;

struct PosePublisher::Entities {
  explicit Entities(const DdsConfig& c) : participant(c, "vigs_publisher") {
    frames.map = c.map_frame_id;
    frames.camera = c.camera_frame_id;
    publisher = participant->create_publisher(fdds::PUBLISHER_QOS_DEFAULT);
    if (publisher == nullptr) throw std::runtime_error("Fast DDS: cannot create the publisher");
    pose = make_writer(c, c.topics.pose, pose_type, c.pose_qos_profile, "pose_qos_profile");
    odom = make_writer(c, c.topics.odom, odom_type, c.pose_qos_profile, "pose_qos_profile");
    tf = make_writer(c, c.topics.tf, tf_type, c.pose_qos_profile, "pose_qos_profile");
    quality =
        make_writer(c, c.topics.pose_quality, quality_type, c.pose_qos_profile, "pose_qos_profile");
    keyframe = make_writer(c, c.topics.keyframe, keyframe_type, c.keyframe_qos_profile,
                           "keyframe_qos_profile");
    status =
        make_writer(c, c.topics.status, status_type, c.status_qos_profile, "status_qos_profile");
  }

  fdds::DataWriter* make_writer(const DdsConfig& c, const std::string& topic_name,
                                fdds::TypeSupport& type, const std::string& profile,
                                const char* key) {
    if (type.register_type(participant.get()) != ReturnCode_t::RETCODE_OK) {
      throw std::runtime_error("Fast DDS: cannot register type " + type.get_type_name());
    }
    fdds::Topic* topic =
        participant->create_topic(topic_name, type.get_type_name(), fdds::TOPIC_QOS_DEFAULT);
    if (topic == nullptr) throw std::runtime_error("Fast DDS: cannot create topic " + topic_name);
    fdds::DataWriterQos qos;
    if (publisher->get_datawriter_qos_from_profile(profile, qos) != ReturnCode_t::RETCODE_OK) {
      throw DdsConfigError(std::string("dds.") + key + ": Fast DDS has no data_writer profile '" +
                           profile + "' (from " + c.qos_source + ")");
    }
    fdds::DataWriter* w = publisher->create_datawriter(topic, qos);
    if (w == nullptr) {
      throw std::runtime_error("Fast DDS: cannot create the writer of " + topic_name +
                               " with profile " + profile + " (" + c.qos_source + ")");
    }
    return w;
  }

  Participant participant;  // first member: destroyed last, with every contained entity
  FrameIds frames;
  fdds::TypeSupport pose_type{new geometry_msgs::msg::dds_::PoseWithCovarianceStamped_PubSubType()};
  fdds::TypeSupport odom_type{new nav_msgs::msg::dds_::Odometry_PubSubType()};
  fdds::TypeSupport tf_type{new tf2_msgs::msg::dds_::TFMessage_PubSubType()};
  fdds::TypeSupport keyframe_type{new geometry_msgs::msg::dds_::PoseStamped_PubSubType()};
  fdds::TypeSupport status_type{new vigs_msgs::msg::dds_::Status_PubSubType()};
  fdds::TypeSupport quality_type{new vigs_msgs::msg::dds_::PoseQuality_PubSubType()};
  fdds::Publisher* publisher = nullptr;
  fdds::DataWriter* pose = nullptr;
  fdds::DataWriter* odom = nullptr;
  fdds::DataWriter* tf = nullptr;
  fdds::DataWriter* keyframe = nullptr;
  fdds::DataWriter* status = nullptr;
  fdds::DataWriter* quality = nullptr;
  // Reused every cycle (their strings and the TF vector keep their capacity).
  geometry_msgs::msg::dds_::PoseWithCovarianceStamped_ pose_msg;
  nav_msgs::msg::dds_::Odometry_ odom_msg;
  tf2_msgs::msg::dds_::TFMessage_ tf_msg;
  geometry_msgs::msg::dds_::PoseStamped_ keyframe_msg;
  vigs_msgs::msg::dds_::Status_ status_msg;
  vigs_msgs::msg::dds_::PoseQuality_ quality_msg;
};

PosePublisher::PosePublisher(const DdsConfig& config, PoseRing& poses, StatusMailbox* status,
                             std::string robot)
    : PosePublisher(
          config, [&poses](PoseSample& s) { return poses.try_pop(s); }, status, std::move(robot)) {}

PosePublisher::PosePublisher(const DdsConfig& config, PoseOverwriteRing& poses,
                             StatusMailbox* status, std::string robot)
    : PosePublisher(
          config, [&poses](PoseSample& s) { return poses.try_pop(s); }, status, std::move(robot)) {}

PosePublisher::PosePublisher(const DdsConfig& config, std::function<bool(PoseSample&)> pop,
                             StatusMailbox* status, std::string robot)
    : pop_pose_(std::move(pop)), status_(status), robot_(std::move(robot)) {
  if (config.enabled) entities_ = std::make_unique<Entities>(config);
}

PosePublisher::~PosePublisher() {
  stop();
}

void PosePublisher::start(const rt::ThreadSpec& spec) {
  if (task_) throw std::logic_error("PosePublisher::start called twice");
  task_ = std::make_unique<rt::PeriodicTask>(
      spec, [this](const rt::PeriodicTask::Cycle& c) { run_cycle(c.wake_ns); });
  task_->start();
}

void PosePublisher::stop() {
  if (!task_) return;
  task_->stop();
  run_cycle(rt::monotonic_ns());  // what the producer pushed before stopping
}

std::size_t PosePublisher::run_cycle(std::int64_t now_ns) {
  std::size_t n = 0;
  PoseSample s;
  while (pop_pose_(s)) {
    ++n;
    if (entities_ == nullptr) {
      discarded_.fetch_add(1, std::memory_order_relaxed);
    } else {
      publish(s);
    }
  }
  if (status_ != nullptr && (!status_started_ || now_ns - last_status_ns_ >= kStatusPeriodNs)) {
    StatusSnapshot snap;
    if (status_->try_pop_latest(snap)) {
      status_started_ = true;
      last_status_ns_ = now_ns;
      if (entities_ == nullptr) {
        discarded_.fetch_add(1, std::memory_order_relaxed);
      } else {
        publish_status(snap);
      }
    }
  }
  return n;
}

void PosePublisher::publish(const PoseSample& s) {
  Entities& e = *entities_;
  if (!fill_pose(s, e.frames, e.pose_msg) || !fill_pose_quality(s, e.frames, e.quality_msg) ||
      !fill_odometry(s, e.frames, e.odom_msg) || !fill_tf(s, e.frames, e.tf_msg)) {
    rejected_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  // All four are written whatever the others return (no short circuit); the quality right
  // after its pose.
  const bool pose_ok = e.pose->write(&e.pose_msg);
  const bool quality_ok = e.quality->write(&e.quality_msg);
  const bool odom_ok = e.odom->write(&e.odom_msg);
  const bool tf_ok = e.tf->write(&e.tf_msg);
  const bool ok = pose_ok && quality_ok && odom_ok && tf_ok;
  if (!ok) write_errors_.fetch_add(1, std::memory_order_relaxed);
  poses_published_.fetch_add(1, std::memory_order_relaxed);
  if (s.keyframe) {
    fill_keyframe(s, e.frames, e.keyframe_msg);
    if (e.keyframe->write(&e.keyframe_msg)) {
      keyframes_published_.fetch_add(1, std::memory_order_relaxed);
    } else {
      write_errors_.fetch_add(1, std::memory_order_relaxed);
    }
  }
}

void PosePublisher::publish_status(const StatusSnapshot& s) {
  Entities& e = *entities_;
  if (!fill_status(s, robot_, e.frames.map, e.status_msg)) {
    rejected_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  if (e.status->write(&e.status_msg)) {
    status_published_.fetch_add(1, std::memory_order_relaxed);
  } else {
    write_errors_.fetch_add(1, std::memory_order_relaxed);
  }
}

namespace {
int matched_readers(fdds::DataWriter* w) {
  fdds::PublicationMatchedStatus st;
  w->get_publication_matched_status(st);
  return st.current_count;
}
}  // namespace

int PosePublisher::pose_subscribers() const {
  return entities_ == nullptr ? 0 : matched_readers(entities_->pose);
}

int PosePublisher::pose_quality_subscribers() const {
  return entities_ == nullptr ? 0 : matched_readers(entities_->quality);
}

bool PosePublisher::wait_for_subscribers(int n, std::chrono::milliseconds timeout) const {
  if (entities_ == nullptr) return false;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    bool all = true;
    for (fdds::DataWriter* w : {entities_->pose, entities_->odom, entities_->tf}) {
      all = all && matched_readers(w) >= n;
    }
    if (all) return true;
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

bool PosePublisher::wait_for_acknowledgments(std::chrono::milliseconds timeout) const {
  if (entities_ == nullptr) return false;
  const eprosima::fastrtps::Duration_t max_wait(static_cast<double>(timeout.count()) / 1e3);
  bool ok = true;
  for (fdds::DataWriter* w : {entities_->pose, entities_->quality, entities_->odom, entities_->tf,
                              entities_->keyframe, entities_->status}) {
    ok = ok && w->wait_for_acknowledgments(max_wait) == ReturnCode_t::RETCODE_OK;
  }
  return ok;
}

PosePublisher::Stats PosePublisher::stats() const noexcept {
  Stats s;
  s.poses_published = poses_published_.load(std::memory_order_relaxed);
  s.keyframes_published = keyframes_published_.load(std::memory_order_relaxed);
  s.status_published = status_published_.load(std::memory_order_relaxed);
  s.rejected = rejected_.load(std::memory_order_relaxed);
  s.write_errors = write_errors_.load(std::memory_order_relaxed);
  s.discarded = discarded_.load(std::memory_order_relaxed);
  return s;
}

}  // namespace vigs::dds
