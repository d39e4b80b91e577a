#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "io/ros_msgs/common.hpp"

namespace vigs::io::ros_msgs {

/// geometry_msgs/msg/PoseStamped: the pose of frame `child` in header.frame_id (e.g. T_w_b of
/// the body in "world"), position in m, orientation as a unit quaternion.
struct PoseStamped {
  Header header;
  Pose pose;
  bool operator==(const PoseStamped&) const = default;
};

template <>
struct MessageTraits<PoseStamped> {
  static constexpr std::string_view kRos2Name = "geometry_msgs/msg/PoseStamped";
  static constexpr std::string_view kRos1Name = "geometry_msgs/PoseStamped";
  static std::string_view ros2msg();
  static std::string_view ros1msg();
};

void encode(const PoseStamped& msg, Encoding encoding, std::vector<std::uint8_t>& out);
void decode(std::span<const std::uint8_t> bytes, Encoding encoding, PoseStamped& out);

}  // namespace vigs::io::ros_msgs
