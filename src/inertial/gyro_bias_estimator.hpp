#pragma once
// Slow gyro-bias estimate from tracking (beyond the VIGS paper, which has none). After each
// GICP result the tracked body rotation between the last two frames, R_trk, is compared with
// the IMU's bias-corrected increment dR(bg) = dR * Exp(J_bg (bg - bg_lin)). The residual
//   r = Log(dR(bg)^T R_trk)
// is, to first order, J_bg * d_bg with J_bg = d(dphi)/dbg (about -dt I), so the per-frame
// least-squares bias correction is d_bg = (J_bg^T J_bg)^-1 J_bg^T r. The estimate moves by
//   bg += clamp(gain * d_bg, max_step)   and then |bg| <= max_bias,
// a first-order low-pass of the per-frame estimates with time constant ~1/gain frames
// (gain 0.1: ~10 frames). Updates whose |r| exceeds the gate (a tracking failure rather than
// bias) are skipped and counted.
#include <Eigen/Core>

#include "core/config/inertial_settings.hpp"
#include "inertial/preintegrator.hpp"

namespace vigs::inertial {

struct GyroBiasEstimatorOptions {
  double gain = 0.1;            ///< per frame
  double max_step_rps = 0.005;  ///< clamp of one update, rad/s
  double max_bias_rps = 0.2;    ///< clamp of |bg|, rad/s
  double gate_rad = 0.0872665;  ///< 5 deg
  double min_dt_s = 1e-3;       ///< shorter intervals carry no bias information

  static GyroBiasEstimatorOptions from(const config::InertialSettings& s);
};

class GyroBiasEstimator {
 public:
  explicit GyroBiasEstimator(const GyroBiasEstimatorOptions& options = {},
                             const Eigen::Vector3d& initial_bias_rps = Eigen::Vector3d::Zero())
      : options_(options), bias_rps_(initial_bias_rps) {}

  /// One update from the interval `pi` (integrated at any linearisation bias) and the tracked
  /// relative body rotation R_bi_bj over the same interval. Returns true when applied.
  bool update(const Preintegrator& pi, const Eigen::Matrix3d& R_bi_bj_tracked);

  [[nodiscard]] const Eigen::Vector3d& bias_rps() const { return bias_rps_; }
  void set_bias_rps(const Eigen::Vector3d& b) { bias_rps_ = b; }
  [[nodiscard]] long updates() const { return updates_; }
  [[nodiscard]] long gated() const { return gated_; }
  [[nodiscard]] long clamped() const { return clamped_; }
  /// Rotation residual of the last call, rad (before the update).
  [[nodiscard]] double last_residual_rad() const { return last_residual_rad_; }

 private:
  GyroBiasEstimatorOptions options_;
  Eigen::Vector3d bias_rps_;
  long updates_ = 0;
  long gated_ = 0;
  long clamped_ = 0;
  double last_residual_rad_ = 0.0;
};

}  // namespace vigs::inertial
