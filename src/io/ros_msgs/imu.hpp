#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "io/ros_msgs/common.hpp"

namespace vigs::io::ros_msgs {

/// sensor_msgs/msg/Imu. Covariances are 3x3 row-major; element 0 = -1 means "not provided".
struct Imu {
  Header header;
  Quaternion orientation;
  std::array<double, 9> orientation_covariance{};  ///< rad^2
  Vector3 angular_velocity;                        ///< rad/s
  std::array<double, 9> angular_velocity_covariance{};
  Vector3 linear_acceleration;  ///< m/s^2
  std::array<double, 9> linear_acceleration_covariance{};
  bool operator==(const Imu&) const = default;
};

template <>
struct MessageTraits<Imu> {
  static constexpr std::string_view kRos2Name = "sensor_msgs/msg/Imu";
  static constexpr std::string_view kRos1Name = "sensor_msgs/Imu";
  static std::string_view ros2msg();
  static std::string_view ros1msg();
};

void encode(const Imu& msg, Encoding encoding, std::vector<std::uint8_t>& out);
void decode(std::span<const std::uint8_t> bytes, Encoding encoding, Imu& out);

}  // namespace vigs::io::ros_msgs
