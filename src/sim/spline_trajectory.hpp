#pragma once
// The camera carrier's motion: a uniform cubic B-spline in time for the position (control
// points every `spacing_m` along the route, one per knot interval), a second scalar cubic
// B-spline for the heading, and small closed-form roll/pitch sway. Everything the IMU needs
// (velocity, acceleration, body angular rate) comes from analytic derivatives.
//
// Body frame (= IMU frame): x forward, y left, z up; R_w_b = Rz(yaw) Ry(pitch) Rx(roll).
// The route starts with a short standstill (repeated control points).
#include <Eigen/Core>
#include <vector>

namespace vigs::sim {

struct TrajectoryParams {
  double spacing_m = 1.2;        ///< control point spacing; speed ~ spacing / knot interval
  double knot_interval_s = 1.0;  ///< uniform B-spline knot interval
  double height_m = 1.3;         ///< body height above the floor
  double standstill_s = 2.0;     ///< at rest at the start (whole knot intervals)
  double pitch_amp_rad = 0.035, pitch_hz = 0.19;
  double roll_amp_rad = 0.025, roll_hz = 0.27;
};

struct BodyState {
  double t_s = 0.0;
  Eigen::Vector3d p_w_m;        ///< position
  Eigen::Vector3d v_w_mps;      ///< velocity
  Eigen::Vector3d a_w_mps2;     ///< acceleration (kinematic, gravity not included)
  Eigen::Matrix3d R_w_b;        ///< orientation
  Eigen::Vector3d omega_b_rps;  ///< angular velocity in the body frame
};

class SplineTrajectory {
 public:
  /// `route_xy_m`: polyline of waypoints (at least 2, no zero-length legs).
  SplineTrajectory(const std::vector<Eigen::Vector2d>& route_xy_m, const TrajectoryParams& p = {});

  /// State at t in [0, duration_s()]; t is clamped into range.
  [[nodiscard]] BodyState state(double t_s) const;
  [[nodiscard]] double duration_s() const { return duration_s_; }
  [[nodiscard]] const std::vector<Eigen::Vector3d>& control_points() const { return ctrl_; }

 private:
  TrajectoryParams p_;
  std::vector<Eigen::Vector3d> ctrl_;
  std::vector<double> yaw_ctrl_;
  double duration_s_ = 0.0;
};

}  // namespace vigs::sim
