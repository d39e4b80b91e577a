// Schema texts in the concatenated-dependency form that rosbag2 (ros2msg) and `mcap convert`
// (ros1msg) write: the message definition, then each dependency after a line of 80 '=' and
// "MSG: pkg/Name". Types are fully qualified so that no reader has to resolve package-relative
// names.
#include <string>

#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/odometry.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/serial_chunk.hpp"
#include "io/ros_msgs/time_reference.hpp"

namespace vigs::io::ros_msgs {
namespace {

const std::string kSep = "\n" + std::string(80, '=') + "\nMSG: ";

std::string dep(const char* name, const char* text) {
  return kSep + name + "\n" + text;
}

// ROS 2 building blocks.
const char* const kTime2 = "int32 sec\nuint32 nanosec\n";
const char* const kHeader2 = "builtin_interfaces/Time stamp\nstring frame_id\n";
const char* const kQuat = "float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n";
const char* const kVec3 = "float64 x\nfloat64 y\nfloat64 z\n";
const char* const kRoi =
    "uint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n";
// ROS 1 building blocks.
const char* const kHeader1 = "uint32 seq\ntime stamp\nstring frame_id\n";

std::string header2_deps() {
  return dep("std_msgs/Header", kHeader2) + dep("builtin_interfaces/Time", kTime2);
}

}  // namespace

std::string_view MessageTraits<Image>::ros2msg() {
  static const std::string s =
      "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\n"
      "uint32 step\nuint8[] data\n" +
      header2_deps();
  return s;
}
std::string_view MessageTraits<Image>::ros1msg() {
  static const std::string s =
      "Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\n"
      "uint32 step\nuint8[] data\n" +
      dep("std_msgs/Header", kHeader1);
  return s;
}

std::string_view MessageTraits<Imu>::ros2msg() {
  static const std::string s =
      "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\n"
      "float64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\n"
      "float64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\n"
      "float64[9] linear_acceleration_covariance\n" +
      header2_deps() + dep("geometry_msgs/Quaternion", kQuat) + dep("geometry_msgs/Vector3", kVec3);
  return s;
}
std::string_view MessageTraits<Imu>::ros1msg() {
  static const std::string s =
      "Header header\ngeometry_msgs/Quaternion orientation\nfloat64[9] orientation_covariance\n"
      "geometry_msgs/Vector3 angular_velocity\nfloat64[9] angular_velocity_covariance\n"
      "geometry_msgs/Vector3 linear_acceleration\nfloat64[9] linear_acceleration_covariance\n" +
      dep("std_msgs/Header", kHeader1) + dep("geometry_msgs/Quaternion", kQuat) +
      dep("geometry_msgs/Vector3", kVec3);
  return s;
}

std::string_view MessageTraits<CameraInfo>::ros2msg() {
  static const std::string s =
      "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\n"
      "float64[] d\nfloat64[9] k\nfloat64[9] r\nfloat64[12] p\nuint32 binning_x\n"
      "uint32 binning_y\nsensor_msgs/RegionOfInterest roi\n" +
      header2_deps() + dep("sensor_msgs/RegionOfInterest", kRoi);
  return s;
}
std::string_view MessageTraits<CameraInfo>::ros1msg() {
  static const std::string s =
      "Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] D\n"
      "float64[9] K\nfloat64[9] R\nfloat64[12] P\nuint32 binning_x\nuint32 binning_y\n"
      "RegionOfInterest roi\n" +
      dep("std_msgs/Header", kHeader1) + dep("sensor_msgs/RegionOfInterest", kRoi);
  return s;
}

std::string_view MessageTraits<PoseStamped>::ros2msg() {
  static const std::string s =
      "std_msgs/Header header\ngeometry_msgs/Pose pose\n" + header2_deps() +
      dep("geometry_msgs/Pose",
          "geometry_msgs/Point position\n"
          "geometry_msgs/Quaternion orientation\n") +
      dep("geometry_msgs/Point", kVec3) + dep("geometry_msgs/Quaternion", kQuat);
  return s;
}
std::string_view MessageTraits<PoseStamped>::ros1msg() {
  static const std::string s =
      "Header header\ngeometry_msgs/Pose pose\n" + dep("std_msgs/Header", kHeader1) +
      dep("geometry_msgs/Pose", "Point position\nQuaternion orientation\n") +
      dep("geometry_msgs/Point", kVec3) + dep("geometry_msgs/Quaternion", kQuat);
  return s;
}

std::string_view MessageTraits<Odometry>::ros2msg() {
  static const std::string s =
      "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n"
      "geometry_msgs/TwistWithCovariance twist\n" +
      header2_deps() +
      dep("geometry_msgs/PoseWithCovariance", "geometry_msgs/Pose pose\nfloat64[36] covariance\n") +
      dep("geometry_msgs/Pose",
          "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n") +
      dep("geometry_msgs/Point", kVec3) + dep("geometry_msgs/Quaternion", kQuat) +
      dep("geometry_msgs/TwistWithCovariance",
          "geometry_msgs/Twist twist\nfloat64[36] covariance\n") +
      dep("geometry_msgs/Twist", "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n") +
      dep("geometry_msgs/Vector3", kVec3);
  return s;
}
std::string_view MessageTraits<Odometry>::ros1msg() {
  static const std::string s =
      "Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n"
      "geometry_msgs/TwistWithCovariance twist\n" +
      dep("std_msgs/Header", kHeader1) +
      dep("geometry_msgs/PoseWithCovariance", "Pose pose\nfloat64[36] covariance\n") +
      dep("geometry_msgs/Pose", "Point position\nQuaternion orientation\n") +
      dep("geometry_msgs/Point", kVec3) + dep("geometry_msgs/Quaternion", kQuat) +
      dep("geometry_msgs/TwistWithCovariance", "Twist twist\nfloat64[36] covariance\n") +
      dep("geometry_msgs/Twist", "Vector3 linear\nVector3 angular\n") +
      dep("geometry_msgs/Vector3", kVec3);
  return s;
}

std::string_view MessageTraits<SerialChunk>::ros2msg() {
  static const std::string s = "builtin_interfaces/Time stamp\nstring port\nuint8[] data\n" +
                               dep("builtin_interfaces/Time", kTime2);
  return s;
}
std::string_view MessageTraits<SerialChunk>::ros1msg() {
  static const std::string s = "time stamp\nstring port\nuint8[] data\n";
  return s;
}

std::string_view MessageTraits<TimeReference>::ros2msg() {
  static const std::string s =
      "std_msgs/Header header\nbuiltin_interfaces/Time time_ref\nstring source\n" + header2_deps();
  return s;
}
std::string_view MessageTraits<TimeReference>::ros1msg() {
  static const std::string s =
      "Header header\ntime time_ref\nstring source\n" + dep("std_msgs/Header", kHeader1);
  return s;
}

}  // namespace vigs::io::ros_msgs
