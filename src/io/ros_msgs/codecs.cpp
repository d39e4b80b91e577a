// The message codecs: each type's field order (visit_fields.hpp) through the archives.
#include "io/ros_msgs/archive.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/image_view.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/odometry.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/serial_chunk.hpp"
#include "io/ros_msgs/time_reference.hpp"
#include "io/ros_msgs/visit_fields.hpp"

namespace vigs::io::ros_msgs {

Time Time::from_ns(std::int64_t t_ns) {
  std::int64_t sec = t_ns / 1'000'000'000;
  std::int64_t ns = t_ns % 1'000'000'000;
  if (ns < 0) {
    ns += 1'000'000'000;
    sec -= 1;
  }
  return Time{static_cast<std::int32_t>(sec), static_cast<std::uint32_t>(ns)};
}

std::string_view message_encoding_name(Encoding encoding) {
  return encoding == Encoding::kRos1 ? "ros1" : "cdr";
}
std::string_view schema_encoding_name(Encoding encoding) {
  return encoding == Encoding::kRos1 ? "ros1msg" : "ros2msg";
}

#define VIGS_ROS_MSG_CODEC(Type, Visitor)                                           \
  void encode(const Type& msg, Encoding encoding, std::vector<std::uint8_t>& out) { \
    detail::encode_with(msg, encoding, out, detail::Visitor{});                     \
  }                                                                                 \
  void decode(std::span<const std::uint8_t> bytes, Encoding encoding, Type& out) {  \
    detail::decode_with(bytes, encoding, out, detail::Visitor{});                   \
  }

VIGS_ROS_MSG_CODEC(Image, VisitImage)
VIGS_ROS_MSG_CODEC(Imu, VisitImu)
VIGS_ROS_MSG_CODEC(CameraInfo, VisitCameraInfo)
VIGS_ROS_MSG_CODEC(PoseStamped, VisitPoseStamped)
VIGS_ROS_MSG_CODEC(Odometry, VisitOdometry)
VIGS_ROS_MSG_CODEC(SerialChunk, VisitSerialChunk)
VIGS_ROS_MSG_CODEC(TimeReference, VisitTimeReference)

#undef VIGS_ROS_MSG_CODEC

void decode(std::span<const std::uint8_t> bytes, Encoding encoding, ImageMeta& out) {
  detail::decode_prefix_with(bytes, encoding, out, detail::VisitImageMeta{});
}
void decode(std::span<const std::uint8_t> bytes, Encoding encoding, ImageView& out) {
  detail::decode_with(bytes, encoding, out, detail::VisitImage{});
}

}  // namespace vigs::io::ros_msgs
