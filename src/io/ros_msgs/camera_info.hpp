#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/ros_msgs/common.hpp"

namespace vigs::io::ros_msgs {

/// sensor_msgs/msg/RegionOfInterest.
struct RegionOfInterest {
  std::uint32_t x_offset = 0, y_offset = 0, height = 0, width = 0;  ///< px
  bool do_rectify = false;
  bool operator==(const RegionOfInterest&) const = default;
};

/// sensor_msgs/msg/CameraInfo (ROS 1 names the arrays D, K, R, P; the layout is the same).
struct CameraInfo {
  Header header;
  std::uint32_t height = 0;      ///< px
  std::uint32_t width = 0;       ///< px
  std::string distortion_model;  ///< "plumb_bob", "equidistant", ...
  std::vector<double> d;         ///< distortion coefficients
  std::array<double, 9> k{};     ///< intrinsics, row-major [fx 0 cx; 0 fy cy; 0 0 1], px
  std::array<double, 9> r{};     ///< rectification rotation, row-major
  std::array<double, 12> p{};    ///< projection, row-major 3x4
  std::uint32_t binning_x = 0;
  std::uint32_t binning_y = 0;
  RegionOfInterest roi;
  bool operator==(const CameraInfo&) const = default;
};

template <>
struct MessageTraits<CameraInfo> {
  static constexpr std::string_view kRos2Name = "sensor_msgs/msg/CameraInfo";
  static constexpr std::string_view kRos1Name = "sensor_msgs/CameraInfo";
  static std::string_view ros2msg();
  static std::string_view ros1msg();
};

void encode(const CameraInfo& msg, Encoding encoding, std::vector<std::uint8_t>& out);
void decode(std::span<const std::uint8_t> bytes, Encoding encoding, CameraInfo& out);

}  // namespace vigs::io::ros_msgs
