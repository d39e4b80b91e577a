#pragma once
#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "io/ros_msgs/common.hpp"

namespace vigs::io::ros_msgs {

/// nav_msgs/msg/Odometry: the pose of `child_frame_id` in header.frame_id and its twist in
/// child_frame_id. uHumans bags carry their ground truth this way on /tesse/odom.
struct Odometry {
  Header header;
  std::string child_frame_id;
  Pose pose;                                  ///< m, unit quaternion
  std::array<double, 36> pose_covariance{};   ///< 6x6 row-major [x y z rx ry rz]
  Vector3 linear_velocity;                    ///< m/s, in child_frame_id
  Vector3 angular_velocity;                   ///< rad/s, in child_frame_id
  std::array<double, 36> twist_covariance{};  ///< 6x6 row-major
  bool operator==(const Odometry&) const = default;
};

template <>
struct MessageTraits<Odometry> {
  static constexpr std::string_view kRos2Name = "nav_msgs/msg/Odometry";
  static constexpr std::string_view kRos1Name = "nav_msgs/Odometry";
  static std::string_view ros2msg();
  static std::string_view ros1msg();
};

void encode(const Odometry& msg, Encoding encoding, std::vector<std::uint8_t>& out);
void decode(std::span<const std::uint8_t> bytes, Encoding encoding, Odometry& out);

}  // namespace vigs::io::ros_msgs
