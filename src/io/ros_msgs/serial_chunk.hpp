#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/ros_msgs/common.hpp"

namespace vigs::io::ros_msgs {

/// vigs_msgs/msg/SerialChunk: raw bytes as read from a serial port, so that replay can feed
/// them through a pseudo-terminal to the real serial driver. Definition (ros2msg):
///   builtin_interfaces/Time stamp   # host time the first byte was read
///   string port                     # device, e.g. "/dev/ttyUSB0"
///   uint8[] data                    # bytes exactly as read
struct SerialChunk {
  Time stamp;
  std::string port;
  std::vector<std::uint8_t> data;
  bool operator==(const SerialChunk&) const = default;
};

template <>
struct MessageTraits<SerialChunk> {
  static constexpr std::string_view kRos2Name = "vigs_msgs/msg/SerialChunk";
  static constexpr std::string_view kRos1Name = "vigs_msgs/SerialChunk";
  static std::string_view ros2msg();
  static std::string_view ros1msg();
};

void encode(const SerialChunk& msg, Encoding encoding, std::vector<std::uint8_t>& out);
void decode(std::span<const std::uint8_t> bytes, Encoding encoding, SerialChunk& out);

}  // namespace vigs::io::ros_msgs
