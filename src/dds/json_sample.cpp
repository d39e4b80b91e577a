#include "dds/json_sample.hpp"

#include <cmath>

namespace vigs::dds {
namespace {

using nlohmann::json;

json num(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

json covariance(const std::array<double, 36>& c) {
  json a = json::array();
  for (double v : c) a.push_back(num(v));
  return a;
}

json header(const std_msgs::msg::dds_::Header_& h) {
  return {{"stamp", {{"sec", h.stamp().sec()}, {"nanosec", h.stamp().nanosec()}}},
          {"frame_id", h.frame_id()}};
}

json vec3(const geometry_msgs::msg::dds_::Vector3_& v) {
  return {{"x", num(v.x())}, {"y", num(v.y())}, {"z", num(v.z())}};
}

json quat(const geometry_msgs::msg::dds_::Quaternion_& q) {
  return {{"x", num(q.x())}, {"y", num(q.y())}, {"z", num(q.z())}, {"w", num(q.w())}};
}

json pose(const geometry_msgs::msg::dds_::Pose_& p) {
  const auto& t = p.position();
  return {{"position", {{"x", num(t.x())}, {"y", num(t.y())}, {"z", num(t.z())}}},
          {"orientation", quat(p.orientation())}};
}

json pose_cov(const geometry_msgs::msg::dds_::PoseWithCovariance_& p) {
  return {{"pose", pose(p.pose())}, {"covariance", covariance(p.covariance())}};
}

}  // namespace

json to_json(const geometry_msgs::msg::dds_::PoseWithCovarianceStamped_& m) {
  return {{"header", header(m.header())}, {"pose", pose_cov(m.pose())}};
}

json to_json(const geometry_msgs::msg::dds_::PoseStamped_& m) {
  return {{"header", header(m.header())}, {"pose", pose(m.pose())}};
}

json to_json(const nav_msgs::msg::dds_::Odometry_& m) {
  const auto& tw = m.twist();
  return {
      {"header", header(m.header())},
      {"child_frame_id", m.child_frame_id()},
      {"pose", pose_cov(m.pose())},
      {"twist",
       {{"twist", {{"linear", vec3(tw.twist().linear())}, {"angular", vec3(tw.twist().angular())}}},
        {"covariance", covariance(tw.covariance())}}}};
}

json to_json(const tf2_msgs::msg::dds_::TFMessage_& m) {
  json transforms = json::array();
  for (const auto& t : m.transforms()) {
    transforms.push_back({{"header", header(t.header())},
                          {"child_frame_id", t.child_frame_id()},
                          {"transform",
                           {{"translation", vec3(t.transform().translation())},
                            {"rotation", quat(t.transform().rotation())}}}});
  }
  return {{"transforms", transforms}};
}

json to_json(const vigs_msgs::msg::dds_::Status_& m) {
  json threads = json::array();
  for (const auto& t : m.threads()) {
    threads.push_back({{"name", t.name()},
                       {"rate_hz", num(t.rate_hz())},
                       {"cycle_p50_ns", t.cycle_p50_ns()},
                       {"cycle_p99_ns", t.cycle_p99_ns()},
                       {"overruns", t.overruns()},
                       {"missed_deadlines", t.missed_deadlines()}});
  }
  json rings = json::array();
  for (const auto& r : m.rings()) {
    rings.push_back({{"name", r.name()},
                     {"depth", r.depth()},
                     {"capacity", r.capacity()},
                     {"drops", r.drops()}});
  }
  json faults = json::array();
  for (const auto& f : m.faults()) faults.push_back({{"name", f.name()}, {"count", f.count()}});
  return {{"header", header(m.header())},
          {"robot", m.robot()},
          {"tracking_state", m.tracking_state()},
          {"frames_tracked", m.frames_tracked()},
          {"gaussian_count", m.gaussian_count()},
          {"mapping_budget_used", num(m.mapping_budget_used())},
          {"threads", threads},
          {"rings", rings},
          {"faults", faults}};
}

json to_json(const vigs_msgs::msg::dds_::PoseQuality_& m) {
  return {{"header", header(m.header())},
          {"frame_index", m.frame_index()},
          {"source", m.source()},
          {"flags", m.flags()},
          {"keyframe", m.keyframe()}};
}

}  // namespace vigs::dds
