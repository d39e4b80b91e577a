#pragma once
// PoseSample -> the ROS 2 messages VIGS publishes. Stamps are the sample's sensor time t_ns.
//  - PoseWithCovarianceStamped: pose of the camera in the map frame, covariance copied as is
//    (PoseSample already uses ROS's row-major [x y z rx ry rz] order);
//  - Odometry: the same pose; child_frame_id = the camera frame, and, as ROS's Odometry message
//    says, the twist is expressed in the child frame: linear = R_w_c^T v_w, angular = omega_c.
//    The sample carries no twist covariance, so it is all zeros (unknown);
//  - TFMessage: one transform map -> camera;
//  - PoseStamped: the keyframe's pose;
//  - vigs_msgs PoseQuality: the same header as the pose, the frame index, source, flags and
//    keyframe bit, so a subscriber tells a tracked pose from a propagated or degraded one.
// Each fill_* returns false (and the caller publishes nothing) when the sample holds a
// non-finite number or a stamp int32 seconds cannot hold: such values never reach the wire.
#include <string>

#include "core/types/pose_sample.hpp"
#include "geometry_msgs.h"
#include "nav_msgs.h"
#include "tf2_msgs.h"
#include "vigs_msgs.h"

namespace vigs::dds {

struct FrameIds {
  std::string map = "map";
  std::string camera = "camera";
};

/// Every number in the sample is finite and the stamp fits builtin_interfaces/Time.
[[nodiscard]] bool publishable(const PoseSample& s) noexcept;

bool fill_pose(const PoseSample& s, const FrameIds& f,
               geometry_msgs::msg::dds_::PoseWithCovarianceStamped_& out);
bool fill_odometry(const PoseSample& s, const FrameIds& f, nav_msgs::msg::dds_::Odometry_& out);
bool fill_tf(const PoseSample& s, const FrameIds& f, tf2_msgs::msg::dds_::TFMessage_& out);
bool fill_keyframe(const PoseSample& s, const FrameIds& f,
                   geometry_msgs::msg::dds_::PoseStamped_& out);
bool fill_pose_quality(const PoseSample& s, const FrameIds& f,
                       vigs_msgs::msg::dds_::PoseQuality_& out);

}  // namespace vigs::dds
