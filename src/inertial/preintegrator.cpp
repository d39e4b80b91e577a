#include "inertial/preintegrator.hpp"

#include "core/geometry/so3.hpp"
#include "inertial/imu_interpolation.hpp"
#include "inertial/so3_integrals.hpp"

namespace vigs::inertial {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using geometry::hat;

namespace {
Vector3d gyro(const ImuSample& s) {
  return {s.gyro_rps[0], s.gyro_rps[1], s.gyro_rps[2]};
}
Vector3d accel(const ImuSample& s) {
  return {s.accel_mps2[0], s.accel_mps2[1], s.accel_mps2[2]};
}
}  // namespace

bool parse_integration_scheme(const std::string& name, IntegrationScheme& out) {
  if (name == "midpoint") {
    out = IntegrationScheme::kMidpoint;
    return true;
  }
  if (name == "zoh") {
    out = IntegrationScheme::kZeroOrderHold;
    return true;
  }
  return false;
}

const char* integration_scheme_name(IntegrationScheme scheme) {
  return scheme == IntegrationScheme::kMidpoint ? "midpoint" : "zoh";
}

void Preintegrator::reset(const ImuSample& start, const Vector3d& bias_gyro_rps,
                          const Vector3d& bias_accel_mps2) {
  bg_ = bias_gyro_rps;
  ba_ = bias_accel_mps2;
  t_start_ns_ = start.t_ns;
  last_ = start;
  steps_ = 0;
  dR_.setIdentity();
  dv_.setZero();
  dp_.setZero();
  jac_.setZero();
  cov_.setZero();
}

bool Preintegrator::integrate(const ImuSample& next) {
  if (next.t_ns < last_.t_ns) return false;
  if (next.t_ns == last_.t_ns) {
    last_ = next;
    return true;
  }
  step(next, 1e-9 * static_cast<double>(next.t_ns - last_.t_ns));
  last_ = next;
  ++steps_;
  return true;
}

bool Preintegrator::integrate_until(std::int64_t t_ns, const ImuSample& next) {
  if (t_ns < last_.t_ns || next.t_ns < t_ns) return false;
  return integrate(interpolate_sample(last_, next, t_ns));
}

void Preintegrator::step(const ImuSample& next, double dt_s) {
  StepJacobians F;
  if (scheme_ == IntegrationScheme::kMidpoint) {
    midpoint_step(next, dt_s, F);
  } else {
    zoh_step(dt_s, F);
  }
  // J <- A J - [Bg Ba]: the biases enter as (w - bg) and (a - ba), so a bias change acts as
  // minus a reading change. A's block structure is used instead of a dense 9x9 product.
  const Mat96 J = jac_;
  jac_.middleRows<3>(3) += F.A_vr * J.topRows<3>();
  jac_.bottomRows<3>() += F.A_pr * J.topRows<3>() + dt_s * J.middleRows<3>(3);
  jac_.topRows<3>() = F.A_rr * J.topRows<3>();
  jac_.leftCols<3>() -= F.Bg;
  jac_.rightCols<3>() -= F.Ba;
  // Sigma <- A Sigma A^T + Bg Qg Bg^T + Ba Qa Ba^T, discrete white noise density^2 / dt.
  Mat9 M = cov_;  // A Sigma
  M.middleRows<3>(3) += F.A_vr * cov_.topRows<3>();
  M.bottomRows<3>() += F.A_pr * cov_.topRows<3>() + dt_s * cov_.middleRows<3>(3);
  M.topRows<3>() = F.A_rr * cov_.topRows<3>();
  cov_ = M;  // (A Sigma) A^T
  cov_.middleCols<3>(3) += M.leftCols<3>() * F.A_vr.transpose();
  cov_.rightCols<3>() += M.leftCols<3>() * F.A_pr.transpose() + dt_s * M.middleCols<3>(3);
  cov_.leftCols<3>() = M.leftCols<3>() * F.A_rr.transpose();
  const double var_g = noise_.gyro_noise_density * noise_.gyro_noise_density / dt_s;
  const double var_a = noise_.accel_noise_density * noise_.accel_noise_density / dt_s;
  cov_.noalias() += var_g * F.Bg * F.Bg.transpose();
  cov_.noalias() += var_a * F.Ba * F.Ba.transpose();
}

// Midpoint: w = (w0 + w1)/2 - bg held over the step; the specific force is the mean of the
// two bias-corrected readings rotated by the increments at either end. A, Bg, Ba are the
// exact derivatives of the step w.r.t. the error state and the gyro / accel readings.
void Preintegrator::midpoint_step(const ImuSample& next, double dt_s, StepJacobians& F) {
  const Vector3d w = 0.5 * (gyro(last_) + gyro(next)) - bg_;
  const Vector3d a0 = accel(last_) - ba_;
  const Vector3d a1 = accel(next) - ba_;
  const Vector3d phi = w * dt_s;
  const Matrix3d dR = geometry::so3_exp<double>(phi);
  const Matrix3d Jr = geometry::so3_right_jacobian<double>(phi);
  const Matrix3d R0 = dR_;
  const Matrix3d R1 = dR_ * dR;
  const Vector3d a_mid = 0.5 * (R0 * a0 + R1 * a1);

  const Matrix3d da_dphi = -0.5 * (R0 * hat<double>(a0) + R1 * hat<double>(a1) * dR.transpose());
  const Matrix3d da_dw = -0.5 * dt_s * R1 * hat<double>(a1) * Jr;
  const Matrix3d da_da = 0.5 * (R0 + R1);
  const double h = 0.5 * dt_s * dt_s;

  F.A_rr = dR.transpose();
  F.A_vr = dt_s * da_dphi;
  F.A_pr = h * da_dphi;
  F.Bg.block<3, 3>(0, 0) = dt_s * Jr;
  F.Bg.block<3, 3>(3, 0) = dt_s * da_dw;
  F.Bg.block<3, 3>(6, 0) = h * da_dw;
  F.Ba.block<3, 3>(3, 0) = dt_s * da_da;
  F.Ba.block<3, 3>(6, 0) = h * da_da;

  dp_ += dv_ * dt_s + h * a_mid;
  dv_ += dt_s * a_mid;
  dR_ = R1;
}

// Exact zero-order hold: the earlier reading (w, a) is held over the step and the rotation
// inside the step is integrated in closed form (see so3_integrals.hpp).
void Preintegrator::zoh_step(double dt_s, StepJacobians& F) {
  const Vector3d w = gyro(last_) - bg_;
  const Vector3d a = accel(last_) - ba_;
  const Vector3d phi = w * dt_s;
  const Matrix3d dR = geometry::so3_exp<double>(phi);
  const Matrix3d Jr = geometry::so3_right_jacobian<double>(phi);
  const So3Series L = so3_first_integral(phi);
  const So3Series Q = so3_second_integral(phi);
  const Vector3d u = L.apply(phi, a);  // int_0^dt Exp(w s) a ds / dt
  const Vector3d q = Q.apply(phi, a);  // double integral / dt^2
  const Matrix3d R0 = dR_;
  const double dt2 = dt_s * dt_s;

  F.A_rr = dR.transpose();
  F.A_vr = -dt_s * R0 * hat<double>(u);
  F.A_pr = -dt2 * R0 * hat<double>(q);
  F.Bg.block<3, 3>(0, 0) = dt_s * Jr;
  F.Bg.block<3, 3>(3, 0) = dt2 * R0 * L.derivative(phi, a);
  F.Bg.block<3, 3>(6, 0) = dt2 * dt_s * R0 * Q.derivative(phi, a);
  F.Ba.block<3, 3>(3, 0) = dt_s * R0 * L.matrix(phi);
  F.Ba.block<3, 3>(6, 0) = dt2 * R0 * Q.matrix(phi);

  dp_ += dv_ * dt_s + dt2 * (R0 * q);
  dv_ += dt_s * (R0 * u);
  dR_ = R0 * dR;
}

DeltaState Preintegrator::predict_with_bias(const Vector3d& bias_gyro_rps,
                                            const Vector3d& bias_accel_mps2) const {
  const Vector3d dbg = bias_gyro_rps - bg_;
  const Vector3d dba = bias_accel_mps2 - ba_;
  DeltaState d;
  d.R = dR_ * geometry::so3_exp<double>(Vector3d(dR_dbg() * dbg));
  d.v_mps = dv_ + dv_dbg() * dbg + dv_dba() * dba;
  d.p_m = dp_ + dp_dbg() * dbg + dp_dba() * dba;
  d.dt_s = dt_s();
  return d;
}

}  // namespace vigs::inertial
