#pragma once
// Subscriber: the DDS subscriber role, for tools (vigs echo) and tests. It owns one participant
// (same transports and QoS file as the publisher) and one reader per subscribed topic, created
// from the dds.reader_qos_profile profile. Callbacks run on Fast DDS's listener thread, one
// sample at a time, in arrival order.
#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dds/dds_config.hpp"
#include "geometry_msgs.h"
#include "nav_msgs.h"
#include "tf2_msgs.h"
#include "vigs_msgs.h"

namespace vigs::dds {

/// The message types VIGS publishes (generated from src/dds/idl). Subscriber::subscribe is
/// instantiated for these: geometry_msgs PoseWithCovarianceStamped_, PoseStamped_,
/// nav_msgs Odometry_, tf2_msgs TFMessage_, vigs_msgs Status_ and PoseQuality_.
class Subscriber {
 public:
  explicit Subscriber(const DdsConfig& config, const std::string& participant_name = "vigs_sub");
  ~Subscriber();
  Subscriber(const Subscriber&) = delete;
  Subscriber& operator=(const Subscriber&) = delete;

  /// Creates a reader of `topic` (wire name, e.g. rt/vigs/pose) for message type Msg.
  template <class Msg>
  void subscribe(const std::string& topic, std::function<void(const Msg&)> on_sample);

  /// Writers matched on `topic` now (0 for a topic not subscribed).
  [[nodiscard]] int matched_writers(const std::string& topic) const;
  /// Waits until every subscribed topic has at least `n` matched writers.
  bool wait_for_writers(int n, std::chrono::milliseconds timeout) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vigs::dds
