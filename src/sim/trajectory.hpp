#pragma once
// What every camera-carrier motion gives the simulator: the body state at a time, with the
// exact derivatives the IMU synthesis needs (sim/imu_synth.hpp). Implementations:
// SplineTrajectory (smooth route) and RealisticMotion (stop-and-go, quick turns, bob,
// vibration).
//
// Body frame (= IMU frame): x forward, y left, z up; R_w_b = Rz(yaw) Ry(pitch) Rx(roll).
#include <Eigen/Core>

namespace vigs::sim {

struct BodyState {
  double t_s = 0.0;
  Eigen::Vector3d p_w_m;        ///< position
  Eigen::Vector3d v_w_mps;      ///< velocity
  Eigen::Vector3d a_w_mps2;     ///< acceleration (kinematic, gravity not included)
  Eigen::Matrix3d R_w_b;        ///< orientation
  Eigen::Vector3d omega_b_rps;  ///< angular velocity in the body frame
};

class Trajectory {
 public:
  virtual ~Trajectory() = default;
  /// State at t in [0, duration_s()]; t is clamped into range.
  [[nodiscard]] virtual BodyState state(double t_s) const = 0;
  [[nodiscard]] virtual double duration_s() const = 0;
};

/// Yaw-pitch-roll angles (rad) and their rates (rad/s) of R_w_b = Rz(yaw) Ry(pitch) Rx(roll).
struct EulerZyx {
  double yaw = 0, pitch = 0, roll = 0;
  double yaw_rate = 0, pitch_rate = 0, roll_rate = 0;
};

/// Fills st.R_w_b and st.omega_b_rps (body angular velocity) from the angles and rates.
void set_attitude(const EulerZyx& e, BodyState& st);

}  // namespace vigs::sim
