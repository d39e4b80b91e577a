#pragma once
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace vigs::io::ros_msgs {

/// Wire encodings of ROS messages inside MCAP.
/// - kCdr:  ROS 2 (MCAP message_encoding "cdr", schema encoding "ros2msg"): XCDR1 little-endian
///          with the 4-byte encapsulation header 00 01 00 00, primitives aligned to their size
///          relative to the end of that header, strings uint32 length incl. NUL.
/// - kRos1: ROS 1 (message_encoding "ros1", schema encoding "ros1msg"), as `mcap convert`
///          writes from ROS 1 bags: little-endian, no alignment, uint32 length-prefixed
///          strings (no NUL) and arrays, Header with seq, time as uint32 secs/nsecs.
enum class Encoding : std::uint8_t { kCdr = 0, kRos1 = 1 };

/// MCAP message_encoding and schema encoding strings of an Encoding.
std::string_view message_encoding_name(Encoding encoding);
std::string_view schema_encoding_name(Encoding encoding);

/// A message could not be decoded: the text names the message type, field and byte offset.
class DecodeError : public std::runtime_error {
 public:
  explicit DecodeError(const std::string& what) : std::runtime_error(what) {}
};

/// builtin_interfaces/Time (ROS 2) / time (ROS 1, written as uint32 secs, uint32 nsecs).
struct Time {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;  ///< 0 .. 999999999
  static Time from_ns(std::int64_t t_ns);
  std::int64_t to_ns() const { return std::int64_t{sec} * 1'000'000'000 + nanosec; }
  bool operator==(const Time&) const = default;
};

/// std_msgs/Header. `seq` exists only in ROS 1 and is ignored by the CDR encoding.
struct Header {
  std::uint32_t seq = 0;
  Time stamp;
  std::string frame_id;
  bool operator==(const Header&) const = default;
};

/// geometry_msgs/Vector3, m or rad/s or m/s^2 depending on the field.
struct Vector3 {
  double x = 0, y = 0, z = 0;
  bool operator==(const Vector3&) const = default;
};

/// geometry_msgs/Point, m.
struct Point {
  double x = 0, y = 0, z = 0;
  bool operator==(const Point&) const = default;
};

/// geometry_msgs/Quaternion (x y z w order, as ROS).
struct Quaternion {
  double x = 0, y = 0, z = 0, w = 1;
  bool operator==(const Quaternion&) const = default;
};

/// geometry_msgs/Pose.
struct Pose {
  Point position;
  Quaternion orientation;
  bool operator==(const Pose&) const = default;
};

/// Names and schema text of a message type; specialised in each message header.
template <class Msg>
struct MessageTraits;

/// ROS type name for an encoding: "sensor_msgs/msg/Image" (kCdr) or "sensor_msgs/Image" (kRos1).
template <class Msg>
std::string_view type_name(Encoding encoding) {
  return encoding == Encoding::kCdr ? MessageTraits<Msg>::kRos2Name : MessageTraits<Msg>::kRos1Name;
}

/// The schema text (ros2msg or ros1msg, with its dependencies appended after
/// "=====...\nMSG: pkg/Name" separators, as rosbag2 and `mcap convert` write).
template <class Msg>
std::string_view schema_text(Encoding encoding) {
  return encoding == Encoding::kCdr ? MessageTraits<Msg>::ros2msg() : MessageTraits<Msg>::ros1msg();
}

/// True if `schema_name` names Msg in either form ("pkg/msg/Name" or "pkg/Name").
template <class Msg>
bool is_type(std::string_view schema_name) {
  return schema_name == MessageTraits<Msg>::kRos2Name ||
         schema_name == MessageTraits<Msg>::kRos1Name;
}

}  // namespace vigs::io::ros_msgs
