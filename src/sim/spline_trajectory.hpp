#pragma once
// The camera carrier's motion: a uniform cubic B-spline in time for the position (control
// points every `spacing_m` along the route, one per knot interval), a second scalar cubic
// B-spline for the heading, and small closed-form roll/pitch sway. Everything the IMU needs
// (velocity, acceleration, body angular rate) comes from analytic derivatives.
//
// The route starts with a short standstill (repeated control points). The path as a function
// of the spline parameter (path()) lets RealisticMotion re-time the same route.
#include <Eigen/Core>
#include <vector>

#include "sim/trajectory.hpp"

namespace vigs::sim {

struct TrajectoryParams {
  double spacing_m = 1.2;        ///< control point spacing; speed ~ spacing / knot interval
  double knot_interval_s = 1.0;  ///< uniform B-spline knot interval
  double height_m = 1.3;         ///< body height above the floor
  double standstill_s = 2.0;     ///< at rest at the start (whole knot intervals)
  double pitch_amp_rad = 0.035, pitch_hz = 0.19;
  double roll_amp_rad = 0.025, roll_hz = 0.27;
};

/// A point of the route as a function of the spline parameter u (knot intervals).
struct PathPoint {
  Eigen::Vector3d p_w_m;
  Eigen::Vector3d dp_du_m;    ///< first derivative w.r.t. u
  Eigen::Vector3d d2p_du2_m;  ///< second derivative w.r.t. u
};

class SplineTrajectory : public Trajectory {
 public:
  /// `route_xy_m`: polyline of waypoints (at least 2, no zero-length legs).
  SplineTrajectory(const std::vector<Eigen::Vector2d>& route_xy_m, const TrajectoryParams& p = {});

  [[nodiscard]] BodyState state(double t_s) const override;
  [[nodiscard]] double duration_s() const override { return duration_s_; }
  /// Route point at parameter u in [0, u_end()] (clamped); t = u * knot_interval_s.
  [[nodiscard]] PathPoint path(double u) const;
  [[nodiscard]] double u_end() const { return duration_s_ / p_.knot_interval_s; }
  /// End of the start standstill in u: the route is at rest, with zero velocity and
  /// acceleration, for u <= u_rest_end().
  [[nodiscard]] double u_rest_end() const { return still_knots_; }
  [[nodiscard]] const TrajectoryParams& params() const { return p_; }
  /// Heading control points (rad, unwrapped); control point k sits at u = k - 1.
  [[nodiscard]] const std::vector<double>& yaw_control_points() const { return yaw_ctrl_; }
  [[nodiscard]] const std::vector<Eigen::Vector3d>& control_points() const { return ctrl_; }

 private:
  TrajectoryParams p_;
  std::vector<Eigen::Vector3d> ctrl_;
  std::vector<double> yaw_ctrl_;
  double duration_s_ = 0.0;
  double still_knots_ = 0.0;
};

}  // namespace vigs::sim
