#include "pipeline/odometry.hpp"

#include "tracking/settings_from_config.hpp"

namespace vigs::pipeline {
namespace {

tracking::Tracker::Setting tracker_setting(const config::RobotConfig& cfg,
                                           const OdometryOptions& options) {
  tracking::Tracker::Setting s = tracking::tracker_setting(cfg.tracking);
  if (options.guess) s.initial_guess = *options.guess;
  return s;
}

}  // namespace

const char* to_string(tracking::InitialGuessMode mode) {
  switch (mode) {
    case tracking::InitialGuessMode::imu:
      return "imu";
    case tracking::InitialGuessMode::constant_velocity:
      return "constant_velocity";
    case tracking::InitialGuessMode::previous_pose:
      return "previous_pose";
  }
  return "unknown";
}

Odometry::Odometry(const config::RobotConfig& cfg, const PinholeCamera& camera,
                   const OdometryOptions& options)
    : mode_(tracker_setting(cfg, options).initial_guess),
      initial_T_w_c_(options.initial_T_w_c),
      inertial_(inertial::InertialFrontendOptions::from(cfg.imu, cfg.extrinsics, cfg.inertial)),
      tracker_(camera, tracker_setting(cfg, options),
               options.initial_T_w_c.value_or(geometry::Pose::Identity())) {}

TrackedFrame Odometry::track(const RgbdView& frame) {
  const std::int64_t t_ns = frame.t_ns;
  const bool imu_mode = mode_ == tracking::InitialGuessMode::imu;
  const bool first = counters_.frames == 0;
  std::optional<geometry::Pose> T_w_c_imu;
  if (imu_mode && !first) {
    T_w_c_imu = inertial_.predict_camera_pose(t_ns);
    if (T_w_c_imu) {
      ++counters_.imu_guesses;
    } else {
      ++counters_.imu_unavailable;
    }
  }
  // The first frame starts at initial_T_w_c (the tracker was built with it).
  const tracking::TrackingOutput out = tracker_.track(frame, T_w_c_imu ? &*T_w_c_imu : nullptr);

  TrackedFrame f;
  f.t_ns = t_ns;
  f.T_w_c = out.T_w_c;
  f.T_w_c_guess = out.T_w_c_guess;
  f.status = out.status;
  f.pose_from_gicp = out.pose_from_gicp;
  f.imu_guess = T_w_c_imu.has_value() && !out.guess_fell_back;
  f.keyframe = out.keyframe;
  f.inlier_ratio = out.gicp.inlier_ratio;
  f.gicp_iterations = out.gicp.iterations;

  ++counters_.frames;
  if (out.keyframe) ++counters_.keyframes;
  switch (out.status) {
    case tracking::TrackingStatus::initialized:
      break;
    case tracking::TrackingStatus::tracked:
      ++counters_.tracked;
      break;
    case tracking::TrackingStatus::lost_low_inliers:
      ++counters_.lost;
      ++counters_.lost_low_inliers;
      break;
    case tracking::TrackingStatus::lost_diverged:
      ++counters_.lost;
      ++counters_.lost_diverged;
      break;
    case tracking::TrackingStatus::lost_degenerate:
      ++counters_.lost;
      ++counters_.lost_degenerate;
      break;
  }

  // The paper's reset: restart the integrator at every frame whose pose is a measurement (and
  // at the first frame, which defines the start). A lost frame's pose is the IMU guess itself,
  // so resetting from it would only restart the integration from its own prediction and lose
  // the velocity; instead the IMU keeps propagating from the last good frame.
  if (imu_mode && (first || out.pose_from_gicp)) {
    if (inertial_.reset_from_tracked(t_ns, out.T_w_c)) ++counters_.imu_resets;
  }
  return f;
}

}  // namespace vigs::pipeline
