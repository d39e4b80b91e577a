#pragma once
// A camera carrier that moves like a person or a legged robot along the smooth route's path
// (SplineTrajectory::path): the same corridors, re-timed by a speed profile (sim/speed_profile)
// with
//   - stop-and-go: standstills of a few seconds mid-route, braking into and accelerating out
//     of them and out of corners at ~1-2 m/s^2 (peak);
//   - quick turns: the heading turns at each corridor corner within a short stretch, at a peak
//     yaw rate of 90-120 deg/s, while the carrier slows to a walking turn speed;
//   - a walking bob (step frequency 1.6-1.9 Hz, cm vertical, with the matching roll, pitch
//     and yaw sway at the step and stride frequencies);
//   - camera vibration (up to ~1 mm and ~0.2 deg, 8-30 Hz).
// Bob and vibration scale with the walking rate, so a standstill is exactly at rest (apart
// from the route's slow sway, as in the smooth profile). Everything is closed form, so the
// IMU gets exact velocity, acceleration and body rate; the plan depends only on the route
// and the seed.
#include <cstdint>
#include <vector>

#include "sim/rng.hpp"
#include "sim/speed_profile.hpp"
#include "sim/spline_trajectory.hpp"

namespace vigs::sim {

struct RealisticMotionParams {
  double cruise_mps = 1.2;      ///< walking speed on straights
  double turn_mps = 0.55;       ///< speed through corners
  double accel_min_mps2 = 1.2;  ///< peak acceleration of a ramp, drawn per ramp
  double accel_max_mps2 = 2.0;
  double turn_rate_min_rps = 1.5708;  ///< peak yaw rate of a corner turn, drawn per corner
  double turn_rate_max_rps = 2.0944;
  double min_turn_rad = 0.2;      ///< heading changes below this are not corners
  double corner_half_u = 1.2;     ///< slow zone: corner +- this (knot intervals)
  double stop_probability = 0.5;  ///< per straight with room for a stop (the first always)
  double stop_min_s = 1.5, stop_max_s = 3.0;
  double step_min_hz = 1.6, step_max_hz = 1.9;
  double bob_m = 0.02;           ///< vertical bob amplitude at cruise
  double bob_roll_rad = 0.025;   ///< roll sway at the stride frequency (step / 2)
  double bob_pitch_rad = 0.008;  ///< pitch nod at the step frequency
  double bob_yaw_rad = 0.012;    ///< yaw sway at the stride frequency
  /// Vibration: two sinusoids per axis at cruise, each with an acceleration amplitude of up
  /// to vibration_mps2 (0.6 mm at 8 Hz, 0.04 mm at 30 Hz) and an angular-rate amplitude of
  /// up to vibration_rps (0.11 deg at 8 Hz, 0.03 deg at 30 Hz).
  double vibration_mps2 = 1.5;
  double vibration_rps = 0.1;
  double vibration_min_hz = 8.0, vibration_max_hz = 30.0;
};

class RealisticMotion : public Trajectory {
 public:
  RealisticMotion(SplineTrajectory path, std::uint64_t seed, const RealisticMotionParams& p = {});

  [[nodiscard]] BodyState state(double t_s) const override;
  [[nodiscard]] double duration_s() const override { return profile_.duration_s(); }

  /// A sinusoid scaled by the walking rate: amp * g(t) * sin(omega t + phase), on `axis`
  /// (world x, y, z for positions; roll, pitch, yaw for angles).
  struct Wave {
    int axis = 0;
    double amp = 0, omega_rps = 0, phase_rad = 0;
  };
  /// A quick turn: the heading changes by `delta_rad` over u in [center - half, center + half].
  struct Turn {
    double center_u = 0, half_u = 0, delta_rad = 0;
  };

 private:
  /// Slow zone or standstill of the plan, in u: [a, b] at `rate` (du/dt), or a dwell at a.
  struct Zone {
    double a = 0, b = 0, rate = 0, dwell_s = 0;
  };
  void plan_turns();
  [[nodiscard]] std::vector<Zone> plan_zones();
  void fill_gap(double u_to, double rate_to);
  void make_waves();

  SplineTrajectory path_;
  RealisticMotionParams p_;
  Rng rng_;
  double spacing_m_ = 1.0;  ///< |dp/du| on straights
  double cruise_rate_ = 1.0, turn_rate_ = 0.5;
  double yaw0_rad_ = 0.0;
  std::vector<Turn> turns_;
  std::vector<Wave> position_waves_, angle_waves_;
  SpeedProfile profile_;
};

}  // namespace vigs::sim
