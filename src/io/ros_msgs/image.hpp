#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/ros_msgs/common.hpp"

namespace vigs::io::ros_msgs {

/// sensor_msgs/msg/Image. Project conventions: "rgb8" or "mono8" colour, "16UC1" depth in mm,
/// "32FC1" depth in m; is_bigendian = 0; step = width * bytes per pixel.
struct Image {
  Header header;
  std::uint32_t height = 0;  ///< rows, px
  std::uint32_t width = 0;   ///< columns, px
  std::string encoding;      ///< "rgb8", "mono8", "16UC1", "32FC1", ...
  std::uint8_t is_bigendian = 0;
  std::uint32_t step = 0;  ///< row length, bytes
  std::vector<std::uint8_t> data;
  bool operator==(const Image&) const = default;
};

template <>
struct MessageTraits<Image> {
  static constexpr std::string_view kRos2Name = "sensor_msgs/msg/Image";
  static constexpr std::string_view kRos1Name = "sensor_msgs/Image";
  static std::string_view ros2msg();
  static std::string_view ros1msg();
};

/// Appends the encoded message to `out` (cleared first). No allocation once `out` has capacity.
void encode(const Image& msg, Encoding encoding, std::vector<std::uint8_t>& out);
/// Decodes `bytes` into `out`. Throws DecodeError naming the field and offset.
void decode(std::span<const std::uint8_t> bytes, Encoding encoding, Image& out);

}  // namespace vigs::io::ros_msgs
