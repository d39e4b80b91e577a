#pragma once
// VIGS messages as JSON, field names as ROS 2 prints them (`ros2 topic echo`), for `vigs echo`.
// Non-finite numbers become null: "nan" never reaches the output.
#include <nlohmann/json.hpp>

#include "geometry_msgs.h"
#include "nav_msgs.h"
#include "tf2_msgs.h"
#include "vigs_msgs.h"

namespace vigs::dds {

nlohmann::json to_json(const geometry_msgs::msg::dds_::PoseWithCovarianceStamped_& m);
nlohmann::json to_json(const geometry_msgs::msg::dds_::PoseStamped_& m);
nlohmann::json to_json(const nav_msgs::msg::dds_::Odometry_& m);
nlohmann::json to_json(const tf2_msgs::msg::dds_::TFMessage_& m);
nlohmann::json to_json(const vigs_msgs::msg::dds_::Status_& m);
nlohmann::json to_json(const vigs_msgs::msg::dds_::PoseQuality_& m);

}  // namespace vigs::dds
