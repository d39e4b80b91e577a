#pragma once
// TopicCatalog: a participant that only listens to discovery (no readers or writers of its
// own) and records every remote writer and reader: topic name, type name, counts. Behind
// `vigs topics`, and `vigs echo TOPIC` for topics outside the VIGS set.
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "dds/dds_config.hpp"

namespace vigs::dds {

struct DiscoveredTopic {
  std::string name;  ///< wire name, e.g. rt/vigs/pose
  std::string type;  ///< e.g. geometry_msgs::msg::dds_::PoseWithCovarianceStamped_
  int writers = 0;   ///< currently known remote writers
  int readers = 0;   ///< currently known remote readers
};

class TopicCatalog {
 public:
  explicit TopicCatalog(const DdsConfig& config);
  ~TopicCatalog();
  TopicCatalog(const TopicCatalog&) = delete;
  TopicCatalog& operator=(const TopicCatalog&) = delete;

  /// Sorted by topic name, then type (a topic seen with two types is listed twice).
  [[nodiscard]] std::vector<DiscoveredTopic> topics() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// "geometry_msgs::msg::dds_::PoseStamped_" -> "geometry_msgs/msg/PoseStamped" (ROS 2's name);
/// other names are returned unchanged.
std::string ros_type_name(const std::string& dds_type);

}  // namespace vigs::dds
