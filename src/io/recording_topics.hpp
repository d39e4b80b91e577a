#pragma once
// Every topic of a VIGS recording, declared once: name, ROS 2 message type, units and the
// frame id written in its header. The simulator writes these (sim/mcap_sink.cpp), the frame
// reader (io/recording/recorded_frames.hpp), the replay (pipeline/recorded_motion.hpp) and the
// evaluation (eval/mcap_trajectory.hpp) read them. Stamps: header stamp = MCAP log time, int64
// nanoseconds on the recording's clock.
#include <array>
#include <string_view>

#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/serial_chunk.hpp"
#include "io/ros_msgs/time_reference.hpp"

namespace vigs::io {

struct RecordedTopic {
  std::string_view name;       ///< MCAP channel topic
  std::string_view ros2_type;  ///< schema name, e.g. "sensor_msgs/msg/Image"
  std::string_view unit;       ///< what the numbers mean
  std::string_view frame_id;   ///< header.frame_id the simulator writes
};

namespace topics {

inline constexpr RecordedTopic kCameraInfo{
    "/vigs/camera_info", "sensor_msgs/msg/CameraInfo",
    "pixels (K: fx, fy, cx, cy; no distortion), one before every colour image", "camera"};
inline constexpr RecordedTopic kRgb{"/vigs/rgb", "sensor_msgs/msg/Image",
                                    "rgb8 or mono8 (8-bit intensity)", "camera"};
inline constexpr RecordedTopic kDepth{
    "/vigs/depth", "sensor_msgs/msg/Image",
    "16UC1 millimetres or 32FC1 metres, 0 = no measurement; registered to the colour image",
    "camera"};
inline constexpr RecordedTopic kImu{"/vigs/imu", "sensor_msgs/msg/Imu",
                                    "angular velocity rad/s, specific force m/s^2, body frame",
                                    "body"};
inline constexpr RecordedTopic kBodyPose{"/vigs/ground_truth/body_pose",
                                         "geometry_msgs/msg/PoseStamped",
                                         "T_w_b: position m, unit quaternion", "world"};
/// Written by the simulator only, right after each frame's depth: which pixels show a walking
/// person, whom the map leaves out by design, so that the evaluation can measure the map on
/// the static scene (eval/render_quality.hpp).
inline constexpr RecordedTopic kDynamicMask{
    "/vigs/ground_truth/dynamic_mask", "sensor_msgs/msg/Image",
    "mono8: 255 where a moving person is the closest surface, 0 elsewhere (simulator ground "
    "truth); same stamp and size as the colour image",
    "camera"};

/// Written by `vigs record` (src/record): the serial port's raw bytes, so that a replay can drive
/// the real serial driver with them, and the GPIO frame-sync edges.
inline constexpr RecordedTopic kImuSerial{"/vigs/imu/serial", "vigs_msgs/msg/SerialChunk",
                                          "the IMU port's bytes exactly as read, stamp = read time",
                                          ""};
inline constexpr RecordedTopic kCameraTrigger{
    "/vigs/camera/trigger", "sensor_msgs/msg/TimeReference",
    "time_ref = the frame-sync edge's kernel stamp (CLOCK_MONOTONIC), source = chip:line",
    "camera"};

/// Written by `vigs run --record`: the pose the tracker published for each frame it tracked.
inline constexpr RecordedTopic kPose{
    "/vigs/pose", "geometry_msgs/msg/PoseStamped",
    "T_w_c: the tracker's camera pose, position m, unit quaternion; stamp = the frame's",
    "map (dds.map_frame_id)"};

/// Written by `vigs run --record`: for each tracked frame (header stamp), the stamp of the newest
/// IMU sample the tracker had used (time_ref), so `vigs replay --as-run` feeds the same samples.
inline constexpr RecordedTopic kTrackerImu{"/vigs/pose/imu_used", "sensor_msgs/msg/TimeReference",
                                           "time_ref = newest IMU sample (t_ns) in the odometry "
                                           "when the frame at header stamp was tracked",
                                           "camera"};

inline constexpr std::array<RecordedTopic, 10> kAll{
    kCameraInfo,  kRgb,       kDepth,         kImu,  kBodyPose,
    kDynamicMask, kImuSerial, kCameraTrigger, kPose, kTrackerImu};

}  // namespace topics

// The declared types are the codecs' types.
static_assert(topics::kCameraInfo.ros2_type ==
              ros_msgs::MessageTraits<ros_msgs::CameraInfo>::kRos2Name);
static_assert(topics::kRgb.ros2_type == ros_msgs::MessageTraits<ros_msgs::Image>::kRos2Name);
static_assert(topics::kDepth.ros2_type == ros_msgs::MessageTraits<ros_msgs::Image>::kRos2Name);
static_assert(topics::kDynamicMask.ros2_type ==
              ros_msgs::MessageTraits<ros_msgs::Image>::kRos2Name);
static_assert(topics::kImu.ros2_type == ros_msgs::MessageTraits<ros_msgs::Imu>::kRos2Name);
static_assert(topics::kBodyPose.ros2_type ==
              ros_msgs::MessageTraits<ros_msgs::PoseStamped>::kRos2Name);
static_assert(topics::kImuSerial.ros2_type ==
              ros_msgs::MessageTraits<ros_msgs::SerialChunk>::kRos2Name);
static_assert(topics::kCameraTrigger.ros2_type ==
              ros_msgs::MessageTraits<ros_msgs::TimeReference>::kRos2Name);
static_assert(topics::kTrackerImu.ros2_type ==
              ros_msgs::MessageTraits<ros_msgs::TimeReference>::kRos2Name);
static_assert(topics::kPose.ros2_type == ros_msgs::MessageTraits<ros_msgs::PoseStamped>::kRos2Name);

}  // namespace vigs::io
