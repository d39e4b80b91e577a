#pragma once
// On-manifold IMU preintegration (Forster et al., "On-Manifold Preintegration for Real-Time
// Visual-Inertial Odometry", TRO 2017): the body-frame increments dR, dv, dp between two
// times at fixed linearisation biases, their first-order bias Jacobians, and the 9x9
// covariance of the error state [dphi, dv, dp] (rotation error on the right:
// dR_true = dR * Exp(dphi)).
//
// The Jacobians are the exact derivatives of the discrete scheme in use (checked by central
// differences in tests/inertial), so predict_with_bias() corrects a bias change to first
// order without re-integration. Nothing allocates: the object is a fixed-size value.
#include <Eigen/Core>
#include <cstdint>
#include <string>

#include "core/config/imu_settings.hpp"
#include "core/types/imu_sample.hpp"

namespace vigs::inertial {

/// How the reading is taken between two samples.
enum class IntegrationScheme {
  kMidpoint,       ///< mean of the two gyro readings; mean of the two rotated accelerations
  kZeroOrderHold,  ///< the earlier reading held; the rotation inside the step integrated exactly
};

/// Parses "midpoint" | "zoh"; returns false on anything else.
bool parse_integration_scheme(const std::string& name, IntegrationScheme& out);
const char* integration_scheme_name(IntegrationScheme scheme);

/// Continuous-time white-noise densities of the sensor.
struct ImuNoise {
  double gyro_noise_density = 0.0;   ///< rad/s/sqrt(Hz)
  double accel_noise_density = 0.0;  ///< m/s^2/sqrt(Hz)
  static ImuNoise from(const config::ImuSettings& s) {
    return {s.gyro_noise_density, s.accel_noise_density};
  }
};

/// Increments over [t_start, t_end] in the body frame at t_start.
struct DeltaState {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  ///< dR_ij
  Eigen::Vector3d v_mps = Eigen::Vector3d::Zero();  ///< dv_ij, m/s
  Eigen::Vector3d p_m = Eigen::Vector3d::Zero();    ///< dp_ij, m
  double dt_s = 0.0;                                ///< t_end - t_start, s
};

class Preintegrator {
 public:
  using Mat9 = Eigen::Matrix<double, 9, 9>;
  using Mat96 = Eigen::Matrix<double, 9, 6>;  ///< rows [dphi; dv; dp], columns [bg, ba]

  Preintegrator() = default;
  Preintegrator(IntegrationScheme scheme, const ImuNoise& noise) : scheme_(scheme), noise_(noise) {}

  /// Starts an empty interval at `start` (its stamp and reading) with linearisation biases.
  void reset(const ImuSample& start, const Eigen::Vector3d& bias_gyro_rps,
             const Eigen::Vector3d& bias_accel_mps2);

  /// Integrates from the last reading to `next`. A sample at the current end time only
  /// replaces the reading; an older one is refused (returns false, state unchanged).
  bool integrate(const ImuSample& next);

  /// Integrates up to t_ns, where `next` is the first sample at or after t_ns: the reading at
  /// t_ns is interpolated linearly between the last reading and `next`.
  bool integrate_until(std::int64_t t_ns, const ImuSample& next);

  /// Increments with the biases changed to (bg, ba), first order in the change.
  [[nodiscard]] DeltaState predict_with_bias(const Eigen::Vector3d& bias_gyro_rps,
                                             const Eigen::Vector3d& bias_accel_mps2) const;
  /// Increments at the linearisation biases.
  [[nodiscard]] DeltaState delta() const { return {dR_, dv_, dp_, dt_s()}; }

  [[nodiscard]] std::int64_t t_start_ns() const { return t_start_ns_; }
  [[nodiscard]] std::int64_t t_end_ns() const { return last_.t_ns; }
  [[nodiscard]] double dt_s() const { return 1e-9 * static_cast<double>(last_.t_ns - t_start_ns_); }
  [[nodiscard]] const ImuSample& last_sample() const { return last_; }
  [[nodiscard]] int steps() const { return steps_; }
  [[nodiscard]] IntegrationScheme scheme() const { return scheme_; }
  [[nodiscard]] const Eigen::Vector3d& bias_gyro_rps() const { return bg_; }
  [[nodiscard]] const Eigen::Vector3d& bias_accel_mps2() const { return ba_; }

  /// d(dphi)/dbg, d(dv)/dbg, d(dv)/dba, d(dp)/dbg, d(dp)/dba (d(dphi)/dba is zero).
  [[nodiscard]] const Mat96& bias_jacobian() const { return jac_; }
  [[nodiscard]] Eigen::Matrix3d dR_dbg() const { return jac_.block<3, 3>(0, 0); }
  [[nodiscard]] Eigen::Matrix3d dv_dbg() const { return jac_.block<3, 3>(3, 0); }
  [[nodiscard]] Eigen::Matrix3d dv_dba() const { return jac_.block<3, 3>(3, 3); }
  [[nodiscard]] Eigen::Matrix3d dp_dbg() const { return jac_.block<3, 3>(6, 0); }
  [[nodiscard]] Eigen::Matrix3d dp_dba() const { return jac_.block<3, 3>(6, 3); }
  /// Covariance of [dphi (rad), dv (m/s), dp (m)] from white sensor noise.
  [[nodiscard]] const Mat9& covariance() const { return cov_; }

 private:
  using Mat93 = Eigen::Matrix<double, 9, 3>;
  /// Derivatives of one step w.r.t. the error state and the readings. The state transition
  /// is A = [[A_rr, 0, 0], [A_vr, I, 0], [A_pr, dt I, I]]; Bg, Ba map reading errors.
  struct StepJacobians {
    Eigen::Matrix3d A_rr, A_vr, A_pr;
    Mat93 Bg = Mat93::Zero();
    Mat93 Ba = Mat93::Zero();
  };
  void step(const ImuSample& next, double dt_s);
  void midpoint_step(const ImuSample& next, double dt_s, StepJacobians& F);
  void zoh_step(double dt_s, StepJacobians& F);

  IntegrationScheme scheme_ = IntegrationScheme::kMidpoint;
  ImuNoise noise_;
  Eigen::Vector3d bg_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d ba_ = Eigen::Vector3d::Zero();
  std::int64_t t_start_ns_ = 0;
  ImuSample last_;
  int steps_ = 0;
  Eigen::Matrix3d dR_ = Eigen::Matrix3d::Identity();
  Eigen::Vector3d dv_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d dp_ = Eigen::Vector3d::Zero();
  Mat96 jac_ = Mat96::Zero();
  Mat9 cov_ = Mat9::Zero();
};

}  // namespace vigs::inertial
