#pragma once
#include <string>

#include "core/config/visitor.hpp"

namespace vigs::config {

/// IMU preintegration and the IMU-seeded initial guess (src/inertial/). The noise densities
/// and gravity live in ImuSettings; the camera-to-body transform in ExtrinsicsSettings.
struct InertialSettings {
  std::string scheme = "midpoint";            ///< midpoint | zoh (exact zero-order hold)
  int buffer_capacity = 4096;                 ///< samples queued ahead of the integrator
  std::string velocity_reset = "difference";  ///< difference (the paper) | imu
  bool estimate_gyro_bias = true;             ///< slow gyro-bias update from GICP rotations
  double gyro_bias_gain = 0.1;                ///< fraction of the per-frame estimate applied
  double gyro_bias_max_step_rps = 0.005;      ///< clamp of one update
  double gyro_bias_max_rps = 0.2;             ///< clamp of the estimate's magnitude
  double gyro_bias_gate_deg = 5.0;            ///< skip updates whose residual is larger
  // Fused mode (tracking.fusion: fused): the 17-state filter.
  bool estimate_accel_bias = true;                   ///< estimate the accelerometer bias
  double fused_initial_velocity_sigma_mps = 0.1;     ///< at the first frame (at rest)
  double fused_initial_gyro_bias_sigma_rps = 0.01;   ///< prior sigma of the gyro bias
  double fused_initial_accel_bias_sigma_mps2 = 0.1;  ///< prior sigma of the accel bias
  /// Process noise the IMU's own model leaves out (the map's frame tilting against gravity as
  /// it drifts, the extrinsic's error, the world frame's motion under GICP): white acceleration
  /// and accelerometer-bias random walk added to the filter's prediction. Without them the
  /// filter trusts its velocity and biases far beyond what GICP can correct (BENCHMARKS.md).
  /// 0.5 (0.2 until 2026-12-05): with 0.2, two of eleven lockstep starts 0-10 frames late on the
  /// seed-5 office went off along one corridor as real-time runs did (toolchain/bench-start-sweep).
  double fused_extra_accel_noise_density = 0.5;  ///< m/s^2/sqrt(Hz)
  /// 0.3 (0.03 until 2026-12-05): the bias state also absorbs what GICP's map frame does to
  /// the accelerometer (g times the map's tilt, in the body frame; a turn swings it onto the
  /// next corridor's axis), so it must follow in seconds: six 3-minute lockstep starts of seed
  /// 5 ended 0.076-0.124 m off at 0.03, 0.055-0.062 m at 0.3. At 1.0 the accelerometer no
  /// longer carries a weakly constrained axis and starts went metres off (BENCHMARKS.md,
  /// twentieth session).
  double fused_extra_accel_random_walk = 0.3;  ///< m/s^3/sqrt(Hz)
  /// Gravity's direction in the map frame as two filter states (inertial/state_propagation.hpp):
  /// prior sigma at the first frame and random walk of the map's tilt; 0 and 0 pin it.
  double fused_gravity_tilt_sigma_rad = 0.0;
  double fused_gravity_tilt_random_walk = 0.0;  ///< rad/sqrt(s)
  /// Zero-velocity update while the IMU shows rest (inertial/stillness_detector.hpp): a
  /// carrier standing in a corridor while people walk past would otherwise let GICP's weak
  /// direction walk the pose centimetres (BENCHMARKS.md, thirty-third session).
  bool fused_zupt = true;
  double fused_zupt_window_s = 0.2;  ///< s: the stillness test looks back at least this far
  /// Detector statistic at or below which the body is still (3 at rest; the simulated office's
  /// standstills read 2.6-5.5, its slowest motion 8 and up).
  double fused_zupt_threshold = 7.0;
  double fused_zupt_sigma_mps = 0.01;  ///< m/s: sigma of the zero-velocity measurement
  /// m/s: no update while the last two fused poses are farther apart than this over their
  /// interval (an even glide reads as rest to the IMU; the standstill's walk was 7 cm/s at most).
  double fused_zupt_max_tracked_speed_mps = 0.1;

  void visit(Visitor& v) {
    v.field("scheme", scheme, {"midpoint", "zoh"},
            "integration between samples: midpoint, or exact zero-order hold");
    v.field("buffer_capacity", buffer_capacity,
            {"samples", 16, 1 << 20,
             "IMU samples queued ahead of the integrator; full = oldest "
             "dropped, counted"});
    v.field("velocity_reset", velocity_reset, {"difference", "imu"},
            "velocity after a GICP result: difference of the last two tracked positions (the "
            "paper), or that difference corrected by the preintegrated motion");
    v.field("estimate_gyro_bias", estimate_gyro_bias,
            "update the gyro bias from the IMU-vs-GICP rotation residual");
    v.field("gyro_bias_gain", gyro_bias_gain,
            {"-", 0.0, 1.0, "per-frame gain of the gyro-bias update"});
    v.field("gyro_bias_max_step_rps", gyro_bias_max_step_rps,
            {"rad/s", 0.0, 1.0, "largest change of the gyro bias in one update"});
    v.field("gyro_bias_max_rps", gyro_bias_max_rps,
            {"rad/s", 0.0, 1.0, "largest gyro-bias magnitude the estimate may reach"});
    v.field("gyro_bias_gate_deg", gyro_bias_gate_deg,
            {"deg", 0.0, 180.0, "skip the update when IMU and GICP rotations differ more"});
    v.field("estimate_accel_bias", estimate_accel_bias,
            "fused tracking: estimate the accelerometer bias in the filter (false: held at 0)");
    v.field("fused_initial_velocity_sigma_mps", fused_initial_velocity_sigma_mps,
            {"m/s", 1e-6, 100.0, "fused tracking: velocity sigma at the first frame (at rest)"});
    v.field("fused_initial_gyro_bias_sigma_rps", fused_initial_gyro_bias_sigma_rps,
            {"rad/s", 1e-9, 10.0, "fused tracking: prior sigma of the gyro bias"});
    v.field("fused_initial_accel_bias_sigma_mps2", fused_initial_accel_bias_sigma_mps2,
            {"m/s^2", 1e-9, 100.0, "fused tracking: prior sigma of the accelerometer bias"});
    v.field("fused_extra_accel_noise_density", fused_extra_accel_noise_density,
            {"m/s^2/sqrt(Hz)", 0.0, 100.0,
             "fused tracking: white acceleration noise added to the prediction for what the "
             "IMU model leaves out (map tilt, extrinsic error)"});
    v.field("fused_extra_accel_random_walk", fused_extra_accel_random_walk,
            {"m/s^3/sqrt(Hz)", 0.0, 100.0,
             "fused tracking: accelerometer-bias random walk added to the imu's"});
    v.field("fused_gravity_tilt_sigma_rad", fused_gravity_tilt_sigma_rad,
            {"rad", 0.0, 0.5,
             "fused tracking: prior sigma of gravity's tilt against the map at the first frame "
             "(0 with a zero random walk: gravity pinned at the start's vertical)"});
    v.field("fused_gravity_tilt_random_walk", fused_gravity_tilt_random_walk,
            {"rad/sqrt(s)", 0.0, 1.0,
             "fused tracking: random walk of gravity's tilt against the map as the map drifts"});
    v.field("fused_zupt", fused_zupt,
            "fused tracking: zero-velocity update while the IMU shows the body at rest");
    v.field("fused_zupt_window_s", fused_zupt_window_s,
            {"s", 0.02, 5.0, "fused tracking: the stillness test looks back at least this far"});
    v.field("fused_zupt_threshold", fused_zupt_threshold,
            {"-", 0.0, 1e6,
             "fused tracking: still when the accelerometer's mean squared spread over the window, "
             "in units of its noise variance (density^2 x rate), is at most this (3 at rest)"});
    v.field("fused_zupt_sigma_mps", fused_zupt_sigma_mps,
            {"m/s", 1e-4, 1.0, "fused tracking: sigma of the zero-velocity measurement"});
    v.field("fused_zupt_max_tracked_speed_mps", fused_zupt_max_tracked_speed_mps,
            {"m/s", 0.0, 10.0,
             "fused tracking: no zero-velocity update while the last two fused poses moved "
             "faster than this (an even glide reads as rest to the IMU)"});
  }
};

}  // namespace vigs::config
