#include "inertial/gyro_bias_estimator.hpp"

#include <Eigen/LU>
#include <cmath>

#include "core/geometry/so3.hpp"

namespace vigs::inertial {

GyroBiasEstimatorOptions GyroBiasEstimatorOptions::from(const config::InertialSettings& s) {
  GyroBiasEstimatorOptions o;
  o.gain = s.gyro_bias_gain;
  o.max_step_rps = s.gyro_bias_max_step_rps;
  o.max_bias_rps = s.gyro_bias_max_rps;
  o.gate_rad = s.gyro_bias_gate_deg * M_PI / 180.0;
  return o;
}

bool GyroBiasEstimator::update(const Preintegrator& pi, const Eigen::Matrix3d& R_bi_bj_tracked) {
  if (pi.dt_s() < options_.min_dt_s) return false;
  const Eigen::Matrix3d R_imu = pi.predict_with_bias(bias_rps_, pi.bias_accel_mps2()).R;
  const Eigen::Vector3d r =
      geometry::so3_log<double>(Eigen::Matrix3d(R_imu.transpose() * R_bi_bj_tracked));
  last_residual_rad_ = r.norm();
  if (!std::isfinite(last_residual_rad_) || last_residual_rad_ > options_.gate_rad) {
    ++gated_;
    return false;
  }
  const Eigen::Matrix3d J = pi.dR_dbg();
  const Eigen::Matrix3d JtJ = J.transpose() * J;
  const Eigen::Vector3d d_bg = JtJ.inverse() * (J.transpose() * r);
  Eigen::Vector3d step = options_.gain * d_bg;
  if (step.norm() > options_.max_step_rps) {
    step *= options_.max_step_rps / step.norm();
    ++clamped_;
  }
  bias_rps_ += step;
  if (bias_rps_.norm() > options_.max_bias_rps) {
    bias_rps_ *= options_.max_bias_rps / bias_rps_.norm();
    ++clamped_;
  }
  ++updates_;
  return true;
}

}  // namespace vigs::inertial
