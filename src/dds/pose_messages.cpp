#include "dds/pose_messages.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "dds/ros_time.hpp"

namespace vigs::dds {
namespace {

// The wire constants (vigs_msgs.idl, PoseQuality.msg) are the core's values, copied as they are.
namespace pq = vigs_msgs::msg::PoseQuality_Constants;
static_assert(pq::SOURCE_TRACKED == static_cast<std::uint8_t>(PoseSource::kTracked));
static_assert(pq::SOURCE_IMU_PROPAGATED == static_cast<std::uint8_t>(PoseSource::kImuPropagated));
static_assert(pq::SOURCE_INITIAL == static_cast<std::uint8_t>(PoseSource::kInitial));
static_assert(pq::SOURCE_GROUND_TRUTH == static_cast<std::uint8_t>(PoseSource::kGroundTruth));
static_assert(pq::FLAG_DEGENERATE == kPoseFlagDegenerate);
static_assert(pq::FLAG_IMU_UNAVAILABLE == kPoseFlagImuUnavailable);
static_assert(pq::FLAG_FRAMES_SKIPPED == kPoseFlagFramesSkipped);
static_assert(pq::FLAG_OUT_OF_ORDER == kPoseFlagOutOfOrder);
static_assert(pq::FLAG_MAP_RESTARTED == kPoseFlagMapRestarted);
static_assert(pq::FLAG_IMU_CORRUPT == kPoseFlagImuCorrupt);
static_assert(pq::FLAG_CAMERA_REOPENED == kPoseFlagCameraReopened);

template <std::size_t N>
bool all_finite(const double (&v)[N]) noexcept {
  for (double x : v) {
    if (!std::isfinite(x)) return false;
  }
  return true;
}

void fill_header(const PoseSample& s, const std::string& frame, std_msgs::msg::dds_::Header_& h) {
  const RosTime t = *to_ros_time(s.t_ns);  // checked by publishable()
  h.stamp().sec(t.sec);
  h.stamp().nanosec(t.nanosec);
  h.frame_id(frame);
}

void fill_pose_body(const PoseSample& s, geometry_msgs::msg::dds_::Pose_& p) {
  p.position().x(s.p_w_m[0]);
  p.position().y(s.p_w_m[1]);
  p.position().z(s.p_w_m[2]);
  p.orientation().x(s.q_w_xyzw[0]);
  p.orientation().y(s.q_w_xyzw[1]);
  p.orientation().z(s.q_w_xyzw[2]);
  p.orientation().w(s.q_w_xyzw[3]);
}

void fill_covariance(const PoseSample& s, std::array<double, 36>& c) {
  for (std::size_t i = 0; i < 36; ++i) c[i] = s.covariance[i];
}

}  // namespace

bool publishable(const PoseSample& s) noexcept {
  return to_ros_time(s.t_ns).has_value() && all_finite(s.p_w_m) && all_finite(s.q_w_xyzw) &&
         all_finite(s.covariance) && all_finite(s.v_w_mps) && all_finite(s.omega_c_radps);
}

bool fill_pose(const PoseSample& s, const FrameIds& f,
               geometry_msgs::msg::dds_::PoseWithCovarianceStamped_& out) {
  if (!publishable(s)) return false;
  fill_header(s, f.map, out.header());
  fill_pose_body(s, out.pose().pose());
  fill_covariance(s, out.pose().covariance());
  return true;
}

bool fill_odometry(const PoseSample& s, const FrameIds& f, nav_msgs::msg::dds_::Odometry_& out) {
  if (!publishable(s)) return false;
  fill_header(s, f.map, out.header());
  out.child_frame_id(f.camera);
  fill_pose_body(s, out.pose().pose());
  fill_covariance(s, out.pose().covariance());
  const Eigen::Quaterniond q_w_c(s.q_w_xyzw[3], s.q_w_xyzw[0], s.q_w_xyzw[1], s.q_w_xyzw[2]);
  const Eigen::Vector3d v_c =
      q_w_c.normalized().conjugate() * Eigen::Vector3d(s.v_w_mps[0], s.v_w_mps[1], s.v_w_mps[2]);
  auto& tw = out.twist().twist();
  tw.linear().x(v_c.x());
  tw.linear().y(v_c.y());
  tw.linear().z(v_c.z());
  tw.angular().x(s.omega_c_radps[0]);
  tw.angular().y(s.omega_c_radps[1]);
  tw.angular().z(s.omega_c_radps[2]);
  out.twist().covariance().fill(0.0);
  return true;
}

bool fill_tf(const PoseSample& s, const FrameIds& f, tf2_msgs::msg::dds_::TFMessage_& out) {
  if (!publishable(s)) return false;
  out.transforms().resize(1);
  geometry_msgs::msg::dds_::TransformStamped_& t = out.transforms()[0];
  fill_header(s, f.map, t.header());
  t.child_frame_id(f.camera);
  t.transform().translation().x(s.p_w_m[0]);
  t.transform().translation().y(s.p_w_m[1]);
  t.transform().translation().z(s.p_w_m[2]);
  t.transform().rotation().x(s.q_w_xyzw[0]);
  t.transform().rotation().y(s.q_w_xyzw[1]);
  t.transform().rotation().z(s.q_w_xyzw[2]);
  t.transform().rotation().w(s.q_w_xyzw[3]);
  return true;
}

bool fill_keyframe(const PoseSample& s, const FrameIds& f,
                   geometry_msgs::msg::dds_::PoseStamped_& out) {
  if (!publishable(s)) return false;
  fill_header(s, f.map, out.header());
  fill_pose_body(s, out.pose());
  return true;
}

bool fill_pose_quality(const PoseSample& s, const FrameIds& f,
                       vigs_msgs::msg::dds_::PoseQuality_& out) {
  if (!publishable(s)) return false;
  fill_header(s, f.map, out.header());
  out.frame_index(s.frame_index);
  out.source(static_cast<std::uint8_t>(s.source));
  out.flags(s.flags);
  out.keyframe(s.keyframe);
  return true;
}

}  // namespace vigs::dds
