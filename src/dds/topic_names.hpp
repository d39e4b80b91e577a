#pragma once
// The VIGS topics on the wire. "rt/" is how ROS 2 names topics in DDS: rt/vigs/pose is the
// ROS 2 topic /vigs/pose. TF is global (/tf), whatever the prefix.
#include <string>

namespace vigs::dds {

struct TopicNames {
  std::string pose;          ///< PoseWithCovarianceStamped
  std::string odom;          ///< Odometry
  std::string keyframe;      ///< PoseStamped, one per new keyframe
  std::string status;        ///< vigs_msgs Status, 1 Hz
  std::string tf;            ///< TFMessage, map -> camera
  std::string pose_quality;  ///< vigs_msgs PoseQuality, one per pose (source and flags)

  static TopicNames from_prefix(const std::string& prefix) {
    return {prefix + "/pose",   prefix + "/odom", prefix + "/keyframe",
            prefix + "/status", "rt/tf",          prefix + "/pose_quality"};
  }
};

/// "/vigs/pose" or "vigs/pose" -> "rt/vigs/pose"; a name already starting with "rt/" is kept.
inline std::string to_wire_topic(const std::string& name) {
  if (name.rfind("rt/", 0) == 0) return name;
  if (!name.empty() && name.front() == '/') return "rt" + name;
  return "rt/" + name;
}

}  // namespace vigs::dds
