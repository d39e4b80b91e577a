#include "pipeline/odometry.hpp"

#include <Eigen/Cholesky>

#include "tracking/settings_from_config.hpp"

namespace vigs::pipeline {
namespace {

tracking::Tracker::Setting tracker_setting(const config::RobotConfig& cfg,
                                           const OdometryOptions& options) {
  tracking::Tracker::Setting s = tracking::tracker_setting(cfg.tracking);
  if (options.guess) s.initial_guess = *options.guess;
  if (options.worker) s.worker = *options.worker;
  return s;
}

}  // namespace

const char* to_string(FusionMode mode) {
  return mode == FusionMode::paper ? "paper" : "fused";
}

bool parse_fusion_mode(const std::string& name, FusionMode& out) {
  if (name == "fused") {
    out = FusionMode::fused;
    return true;
  }
  if (name == "paper") {
    out = FusionMode::paper;
    return true;
  }
  return false;
}

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
               options.initial_T_w_c.value_or(geometry::Pose::Identity())) {
  if (options.fusion) {
    fusion_ = *options.fusion;
  } else if (!parse_fusion_mode(cfg.tracking.fusion, fusion_)) {
    fusion_ = FusionMode::fused;  // the config schema admits only the two names
  }
}

namespace {

/// Covariance of [x y z rx ry rz] about the camera position from the information of
/// xi = [w; v] about the world origin: dp_c = v - [p_c]x w (v = dp_c + [p_c]x w).
bool pose_covariance(const tracking::Matrix6d& Y, const Eigen::Vector3d& p_c, double* out) {
  const Eigen::LLT<tracking::Matrix6d> llt(Y);
  if (llt.info() != Eigen::Success) return false;
  const tracking::Matrix6d C = llt.solve(tracking::Matrix6d::Identity());
  tracking::Matrix6d A = tracking::Matrix6d::Zero();
  A.topLeftCorner<3, 3>() = -geometry::hat<double>(p_c);
  A.topRightCorner<3, 3>().setIdentity();
  A.bottomLeftCorner<3, 3>().setIdentity();
  const tracking::Matrix6d S = A * C * A.transpose();
  if (!S.allFinite()) return false;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) out[r * 6 + c] = 0.5 * (S(r, c) + S(c, r));
  }
  return true;
}

}  // namespace

TrackedFrame Odometry::track(const RgbdView& frame) {
  const std::int64_t t_ns = frame.t_ns;
  const bool imu_mode = mode_ == tracking::InitialGuessMode::imu;
  const bool first = counters_.frames == 0;
  const bool fused = imu_mode && fusion_ == FusionMode::fused;
  std::optional<geometry::Pose> T_w_c_imu;
  if (imu_mode && !first) {
    if (fused) {
      const auto pred = inertial_.predict_camera_pose_fused(t_ns);
      if (pred) {
        T_w_c_imu = pred->T_w_c;
        const Eigen::LLT<tracking::Matrix6d> llt(pred->covariance);
        if (llt.info() == Eigen::Success) {
          tracker_.set_pose_prior(pred->T_w_c, llt.solve(tracking::Matrix6d::Identity()));
        }
      }
    } else {
      T_w_c_imu = inertial_.predict_camera_pose(t_ns);
    }
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
  f.held = out.held;
  f.reinitialized = out.reinitialized;
  f.inlier_ratio = out.gicp.inlier_ratio;
  f.gicp_iterations = out.gicp.iterations;
  f.gicp_verdict = out.gicp.verdict;
  f.prior_used = out.prior_used;
  f.degenerate = out.degenerate;
  f.moving_points = out.moving_points;
  if (out.pose_from_gicp) {
    f.covariance_valid = pose_covariance(out.information, out.T_w_c.translation(), f.covariance);
  }

  ++counters_.frames;
  if (out.keyframe) ++counters_.keyframes;
  if (out.reinitialized) ++counters_.reinitializations;
  if (out.degenerate) ++counters_.degenerate;
  counters_.moving_points += out.moving_points;
  switch (out.status) {
    case tracking::TrackingStatus::initialized:
      break;
    case tracking::TrackingStatus::tracked:
      // a pose GICP left at max_iterations is still used, but counted apart, not as tracked
      if (out.gicp.verdict == tracking::GicpVerdict::not_converged)
        ++counters_.not_converged;
      else
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
  // A map restart after lost frames starts the IMU state again too, as at the first frame (at
  // rest, at the restart pose): the velocity it carried through the lost frames is what lost
  // them, and a guess from it misses the new map at once (measured: with the old velocity kept,
  // a restarted fused run was lost again at the next frame, 287 restarts in 3 minutes).
  if (imu_mode && out.reinitialized) inertial_.restart();
  if (imu_mode && (first || out.pose_from_gicp || out.reinitialized)) {
    if (fused) {
      if (inertial_.update_fused(t_ns, out.T_w_c, out.information)) {
        ++counters_.imu_resets;
        ++counters_.fused_updates;
      }
      counters_.zero_velocity_updates = inertial_.counters().zero_velocity_updates;
      counters_.zupt_gated = inertial_.counters().zupt_gated;
    } else if (inertial_.reset_from_tracked(t_ns, out.T_w_c)) {
      ++counters_.imu_resets;
    }
  }
  return f;
}

}  // namespace vigs::pipeline
