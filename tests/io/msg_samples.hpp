#pragma once
// Sample messages with every field set to a distinct, non-default value, shared by the io tests
// and the conformance writer.
#include <cstdint>

#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/odometry.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/serial_chunk.hpp"

namespace vigs::io::test {

inline ros_msgs::Header sample_header(int i, const char* frame) {
  ros_msgs::Header h;
  h.seq = static_cast<std::uint32_t>(100 + i);
  h.stamp = ros_msgs::Time{1700000000 + i, static_cast<std::uint32_t>(123456789 + i)};
  h.frame_id = frame;
  return h;
}

inline ros_msgs::Image sample_image(int i, bool depth) {
  ros_msgs::Image m;
  m.header = sample_header(i, depth ? "depth_cam" : "left_cam");
  m.width = 7;
  m.height = 5;
  m.encoding = depth ? "16UC1" : "rgb8";
  m.is_bigendian = 0;
  m.step = m.width * (depth ? 2 : 3);
  m.data.resize(std::size_t{m.step} * m.height);
  for (std::size_t k = 0; k < m.data.size(); ++k) m.data[k] = static_cast<std::uint8_t>(k * 7 + i);
  return m;
}

inline ros_msgs::Imu sample_imu(int i) {
  ros_msgs::Imu m;
  m.header = sample_header(i, "imu");
  m.orientation = {0.1 + i, -0.2, 0.3, 0.9};
  for (int k = 0; k < 9; ++k) {
    m.orientation_covariance[k] = -1.0 + k * 0.5;
    m.angular_velocity_covariance[k] = 1e-4 * (k + 1);
    m.linear_acceleration_covariance[k] = 2e-3 * (k + 1) + i;
  }
  m.angular_velocity = {0.01 * i, -0.02, 0.0375};
  m.linear_acceleration = {0.15, -9.81, 0.3 + i};
  return m;
}

inline ros_msgs::CameraInfo sample_camera_info(int i) {
  ros_msgs::CameraInfo m;
  m.header = sample_header(i, "left_cam");
  m.width = 720;
  m.height = 480;
  m.distortion_model = "plumb_bob";
  m.d = {0.01, -0.002, 0.0003, 0.00004, 0.5 + i};
  m.k = {415.69219381653056, 0, 360, 0, 415.69219381653056, 240, 0, 0, 1};
  m.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  m.p = {415.69219381653056, 0, 360, 0, 0, 415.69219381653056, 240, 0, 0, 0, 1, 0.25};
  m.binning_x = 1;
  m.binning_y = 2;
  m.roi = {3, 4, 100, 200, true};
  return m;
}

inline ros_msgs::PoseStamped sample_pose(int i) {
  ros_msgs::PoseStamped m;
  m.header = sample_header(i, "world");
  m.pose.position = {1.5 + i, -2.25, 0.125};
  m.pose.orientation = {0.0, 0.0, 0.38268343236508978, 0.92387953251128674};
  return m;
}

inline ros_msgs::Odometry sample_odometry(int i) {
  ros_msgs::Odometry m;
  m.header = sample_header(i, "world");
  m.child_frame_id = "base_link_gt";
  m.pose.position = {10.0 + i, -3.5, 1.25};
  m.pose.orientation = {0.1, 0.2, 0.3, 0.92736184954957035};
  for (int k = 0; k < 36; ++k) {
    m.pose_covariance[k] = 0.001 * k + i;
    m.twist_covariance[k] = -0.5 * k;
  }
  m.linear_velocity = {1.5, -0.25, 0.0625 * i};
  m.angular_velocity = {0.01, 0.02, -1.5};
  return m;
}

inline ros_msgs::SerialChunk sample_serial(int i) {
  ros_msgs::SerialChunk m;
  m.stamp = ros_msgs::Time{1700000000 + i, 5000u + static_cast<std::uint32_t>(i)};
  m.port = "/dev/ttyUSB0";
  for (int k = 0; k < 37 + i; ++k) m.data.push_back(static_cast<std::uint8_t>(0xFA + k));
  return m;
}

}  // namespace vigs::io::test
