#pragma once
// Window-by-window check of preintegration against a ground-truth state trajectory (what
// `vigs eval imu` prints): consecutive, non-overlapping windows [t_i, t_j] of about
// `window_s`, both ends at ground-truth stamps. At each window start the ground-truth R, p, v
// (and, with BiasSource::kGroundTruth, its biases) seed the prediction of t_j.
#include <Eigen/Core>
#include <cstdint>
#include <span>

#include "core/types/imu_sample.hpp"
#include "inertial/euroc_csv.hpp"
#include "inertial/preintegrator.hpp"

namespace vigs::inertial {

enum class BiasSource { kGroundTruth, kZero };

struct WindowEvalOptions {
  double window_s = 1.0;
  BiasSource bias = BiasSource::kGroundTruth;
  IntegrationScheme scheme = IntegrationScheme::kMidpoint;
  ImuNoise noise;
  double gravity_mps2 = 9.81;
  double max_gap_s = 0.05;  ///< windows with a larger IMU gap are skipped (and counted)
};

struct ErrorStats {
  double rms = 0.0;
  double max = 0.0;
};

struct WindowEvalResult {
  int windows = 0;
  int skipped_gap = 0;  ///< windows skipped because of an IMU gap
  double mean_window_s = 0.0;
  ErrorStats rotation_deg;  ///< angle of R_pred^T R_gt at t_j
  ErrorStats velocity_mps;  ///< |v_pred - v_gt|
  ErrorStats position_m;    ///< |p_pred - p_gt|
  /// RMS over windows of the predicted standard deviation, sqrt(trace) of each 3x3 block of
  /// the preintegration covariance: a magnitude check of the noise model.
  double sigma_rotation_deg = 0.0;
  double sigma_velocity_mps = 0.0;
  double sigma_position_m = 0.0;
};

/// Throws std::invalid_argument when window_s <= 0 or the streams do not overlap by at least
/// one window.
WindowEvalResult evaluate_imu_windows(std::span<const ImuSample> imu,
                                      std::span<const GroundTruthState> gt,
                                      const WindowEvalOptions& options);

}  // namespace vigs::inertial
