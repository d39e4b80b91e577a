#pragma once
#include <span>
#include <string>
#include <vector>

#include "io/ros_msgs/common.hpp"

namespace vigs::io::ros_msgs {

/// sensor_msgs/msg/TimeReference: an external time reference. VIGS records each rising edge of
/// a camera's GPIO frame-sync line as one: header.stamp = time_ref = the edge's kernel stamp
/// (CLOCK_MONOTONIC), header.seq (ROS 1) the edge's index, source the line ("gpiochip0:17").
struct TimeReference {
  Header header;
  Time time_ref;
  std::string source;
  bool operator==(const TimeReference&) const = default;
};

template <>
struct MessageTraits<TimeReference> {
  static constexpr std::string_view kRos2Name = "sensor_msgs/msg/TimeReference";
  static constexpr std::string_view kRos1Name = "sensor_msgs/TimeReference";
  static std::string_view ros2msg();
  static std::string_view ros1msg();
};

void encode(const TimeReference& msg, Encoding encoding, std::vector<std::uint8_t>& out);
void decode(std::span<const std::uint8_t> bytes, Encoding encoding, TimeReference& out);

}  // namespace vigs::io::ros_msgs
