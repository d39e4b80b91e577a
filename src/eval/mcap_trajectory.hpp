#pragma once
// Trajectories from recordings: the PoseStamped messages of one topic of an MCAP file (e.g. the
// simulator's ground truth, io::topics::kBodyPose), stamped by their header.
#include <string>

#include "eval/trajectory.hpp"
#include "io/recording_topics.hpp"

namespace vigs::eval {

/// Throws TrajectoryFileError when the file cannot be read, the topic is missing or holds no
/// PoseStamped messages, or the recording is damaged before the first pose.
Trajectory load_mcap_trajectory(const std::string& path, const std::string& topic);

/// A ".mcap" path reads `mcap_topic`; anything else is a TUM or KITTI text file.
Trajectory load_any_trajectory(const std::string& path, const std::string& mcap_topic = std::string(
                                                            io::topics::kBodyPose.name));

}  // namespace vigs::eval
