// Preintegration: bias Jacobians against central differences of re-integration, closed-form
// motions, exact window cuts, and the covariance against a Monte-Carlo estimate.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/geometry/so3.hpp"
#include "inertial/nav_state.hpp"
#include "inertial/preintegrate_window.hpp"
#include "inertial/preintegrator.hpp"
#include "inertial/so3_integrals.hpp"
#include "inertial/synthetic_motion.hpp"

namespace vigs::inertial {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

ImuSample make_sample(std::int64_t t_ns, const Vector3d& w, const Vector3d& a) {
  ImuSample s;
  s.t_ns = t_ns;
  for (int k = 0; k < 3; ++k) {
    s.gyro_rps[k] = w[k];
    s.accel_mps2[k] = a[k];
  }
  return s;
}

// Fast, irregularly spaced readings of the synthetic motion (rates up to ~2 rad/s).
std::vector<ImuSample> jittered_samples(double duration_s, double rate_hz, unsigned seed) {
  SyntheticMotion motion;
  motion.ang_amp_rad = {0.6, 0.5, 1.2};
  motion.ang_freq_rps = {2.1, 1.7, 1.3};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  std::vector<ImuSample> out;
  const double dt = 1.0 / rate_hz;
  for (int k = 0; k * dt <= duration_s + 1e-12; ++k) {
    const double t = k * dt + (k > 0 ? jitter(rng) * dt : 0.0);
    out.push_back(
        motion.sample(static_cast<std::int64_t>(std::llround(t * 1e9)), Vector3d(0, 0, -9.81)));
  }
  return out;
}

DeltaState integrate_all(const std::vector<ImuSample>& samples, IntegrationScheme scheme,
                         const Vector3d& bg, const Vector3d& ba, Preintegrator* out = nullptr) {
  Preintegrator pi(scheme, ImuNoise{1.7e-4, 2e-3});
  // Cut the window strictly inside the first and last sample to exercise interpolation.
  const std::int64_t t0 = samples.front().t_ns + 1'234'567;
  const std::int64_t t1 = samples.back().t_ns - 2'345'678;
  EXPECT_TRUE(preintegrate_window(samples, t0, t1, bg, ba, pi));
  if (out) *out = pi;
  return pi.delta();
}

class BiasJacobian : public ::testing::TestWithParam<IntegrationScheme> {};

TEST_P(BiasJacobian, EveryBlockMatchesCentralDifferences) {
  const auto samples = jittered_samples(0.8, 200.0, 7);
  const Vector3d bg(0.01, -0.02, 0.015), ba(0.05, -0.1, 0.08);
  Preintegrator pi;
  const DeltaState d0 = integrate_all(samples, GetParam(), bg, ba, &pi);
  ASSERT_GT(pi.steps(), 100);

  const double h = 1e-6;
  Eigen::Matrix<double, 9, 6> numeric;
  for (int c = 0; c < 6; ++c) {
    Vector3d dbg = Vector3d::Zero(), dba = Vector3d::Zero();
    (c < 3 ? dbg[c] : dba[c - 3]) = h;
    const DeltaState dp = integrate_all(samples, GetParam(), bg + dbg, ba + dba);
    const DeltaState dm = integrate_all(samples, GetParam(), bg - dbg, ba - dba);
    numeric.block<3, 1>(0, c) = (geometry::so3_log<double>(Matrix3d(d0.R.transpose() * dp.R)) -
                                 geometry::so3_log<double>(Matrix3d(d0.R.transpose() * dm.R))) /
                                (2 * h);
    numeric.block<3, 1>(3, c) = (dp.v_mps - dm.v_mps) / (2 * h);
    numeric.block<3, 1>(6, c) = (dp.p_m - dm.p_m) / (2 * h);
  }
  const auto& J = pi.bias_jacobian();
  const char* names[3][2] = {{"dR/dbg", "dR/dba"}, {"dv/dbg", "dv/dba"}, {"dp/dbg", "dp/dba"}};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 2; ++c) {
      const Matrix3d a = J.block<3, 3>(3 * r, 3 * c);
      const Matrix3d n = numeric.block<3, 3>(3 * r, 3 * c);
      EXPECT_LT((a - n).norm(), 1e-7 * std::max(1.0, n.norm())) << names[r][c] << "\nanalytic\n"
                                                                << a << "\nnumeric\n"
                                                                << n;
    }
  }
  EXPECT_GT(pi.dR_dbg().norm(), 0.5);  // not trivially zero
  EXPECT_EQ((pi.bias_jacobian().block<3, 3>(0, 3).norm()), 0.0);
}

TEST_P(BiasJacobian, PredictWithBiasIsSecondOrderAccurate) {
  const auto samples = jittered_samples(0.5, 200.0, 3);
  const Vector3d bg(0.01, -0.02, 0.015), ba(0.05, -0.1, 0.08);
  Preintegrator pi;
  integrate_all(samples, GetParam(), bg, ba, &pi);
  double prev_err = 0.0;
  for (double s : {1e-2, 1e-3}) {
    const Vector3d dbg = s * Vector3d(0.3, -0.5, 0.2), dba = s * Vector3d(-1.0, 0.4, 0.7);
    const DeltaState corrected = pi.predict_with_bias(bg + dbg, ba + dba);
    const DeltaState reintegrated = integrate_all(samples, GetParam(), bg + dbg, ba + dba);
    const double err =
        geometry::so3_log<double>(Matrix3d(corrected.R.transpose() * reintegrated.R)).norm() +
        (corrected.v_mps - reintegrated.v_mps).norm() + (corrected.p_m - reintegrated.p_m).norm();
    const DeltaState uncorrected = pi.delta();
    const double err0 = (uncorrected.v_mps - reintegrated.v_mps).norm();
    EXPECT_LT(err, 0.05 * err0) << "step " << s;
    if (prev_err > 0.0) {
      EXPECT_LT(err, prev_err * 0.03);  // quadratic: 100x smaller
    }
    prev_err = err;
  }
}

INSTANTIATE_TEST_SUITE_P(Schemes, BiasJacobian,
                         ::testing::Values(IntegrationScheme::kMidpoint,
                                           IntegrationScheme::kZeroOrderHold),
                         [](const auto& param_info) {
                           return std::string(integration_scheme_name(param_info.param));
                         });

// Readings from f(t) at `rate_hz` over [0, T]; integrates with the given scheme.
template <class F>
Preintegrator integrate_function(F reading, double T, double rate_hz, IntegrationScheme scheme) {
  Preintegrator pi(scheme, ImuNoise{});
  const auto n = static_cast<int>(std::llround(T * rate_hz));
  auto t_ns = [&](int k) { return static_cast<std::int64_t>(std::llround(k * 1e9 / rate_hz)); };
  pi.reset(reading(t_ns(0)), Vector3d::Zero(), Vector3d::Zero());
  for (int k = 1; k <= n; ++k) pi.integrate(reading(t_ns(k)));
  return pi;
}

TEST(ClosedForm, ConstantAngularRateWithBodyFixedForce) {
  // Rotation about z at w with constant body specific force a: closed-form integrals.
  const double w = 1.3, T = 1.5;
  const Vector3d a(0.7, 0.0, -0.4);
  auto reading = [&](std::int64_t t) { return make_sample(t, Vector3d(0, 0, w), a); };
  const double s = std::sin(w * T), c = std::cos(w * T);
  const Vector3d dv(a.x() * s / w, a.x() * (1 - c) / w, a.z() * T);
  const Vector3d dp(a.x() * (1 - c) / (w * w), a.x() * (T - s / w) / w, 0.5 * a.z() * T * T);
  const Matrix3d dR = Eigen::AngleAxisd(w * T, Vector3d::UnitZ()).toRotationMatrix();
  // Midpoint at a high rate: reproduced to 1e-6.
  {
    const DeltaState d =
        integrate_function(reading, T, 5000.0, IntegrationScheme::kMidpoint).delta();
    EXPECT_NEAR(d.dt_s, T, 1e-12);
    EXPECT_LT((d.R - dR).norm(), 1e-6);
    EXPECT_LT((d.v_mps - dv).norm(), 1e-6);
    EXPECT_LT((d.p_m - dp).norm(), 1e-6);
  }
  // The exact zero-order hold is exact for constant readings at any rate.
  {
    const DeltaState d =
        integrate_function(reading, T, 200.0, IntegrationScheme::kZeroOrderHold).delta();
    EXPECT_LT((d.R - dR).norm(), 1e-12);
    EXPECT_LT((d.v_mps - dv).norm(), 1e-11);
    EXPECT_LT((d.p_m - dp).norm(), 1e-11);
  }
}

TEST(ClosedForm, ConstantAccelerationUnderGravity) {
  // Fixed attitude, constant world acceleration: v = v0 + alpha T, p = p0 + v0 T + alpha T^2/2.
  const Vector3d g(0, 0, -9.81), alpha(0.4, -0.3, 0.25), v0(0.2, 0.1, -0.05), p0(1, 2, 3);
  const Matrix3d R0 = geometry::so3_exp<double>(Vector3d(0.3, -0.2, 1.0));
  const Vector3d f_b = R0.transpose() * (alpha - g);
  auto reading = [&](std::int64_t t) { return make_sample(t, Vector3d::Zero(), f_b); };
  const double T = 2.0;
  for (auto scheme : {IntegrationScheme::kMidpoint, IntegrationScheme::kZeroOrderHold}) {
    const DeltaState d = integrate_function(reading, T, 1000.0, scheme).delta();
    const NavState s1 = predict_nav_state({R0, p0, v0}, d, g);
    EXPECT_LT((s1.R_w_b - R0).norm(), 1e-12);
    EXPECT_LT((s1.v_w_b_mps - (v0 + alpha * T)).norm(), 1e-6);
    EXPECT_LT((s1.p_w_b_m - (p0 + v0 * T + 0.5 * alpha * T * T)).norm(), 1e-6);
  }
}

TEST(ClosedForm, CircularMotionWithKnownVelocity) {
  // Body on a circle of radius r at rate W about world z, heading along the tangent, tilted by
  // a fixed roll/pitch R_t: R(t) = Rz(W t) R_t, p = c + r (cos, sin, 0), v = r W (-sin, cos, 0).
  const double r = 2.0, W = 0.8, T = 3.0;
  const Vector3d g(0, 0, -9.81), c(0.5, -1.0, 1.5);
  const Matrix3d Rt = geometry::so3_exp<double>(Vector3d(0.2, -0.15, 0.0));
  auto state = [&](double t) {
    const Matrix3d Rz = Eigen::AngleAxisd(W * t, Vector3d::UnitZ()).toRotationMatrix();
    return NavState{Rz * Rt, c + r * Vector3d(std::cos(W * t), std::sin(W * t), 0.0),
                    r * W * Vector3d(-std::sin(W * t), std::cos(W * t), 0.0)};
  };
  auto reading = [&](std::int64_t t_ns) {
    const double t = 1e-9 * static_cast<double>(t_ns);
    const NavState s = state(t);
    const Vector3d acc = -r * W * W * Vector3d(std::cos(W * t), std::sin(W * t), 0.0);
    return make_sample(t_ns, Rt.transpose() * Vector3d(0, 0, W), s.R_w_b.transpose() * (acc - g));
  };
  const DeltaState d = integrate_function(reading, T, 5000.0, IntegrationScheme::kMidpoint).delta();
  const NavState s1 = predict_nav_state(state(0.0), d, g);
  const NavState truth = state(T);
  EXPECT_LT(geometry::so3_log<double>(Matrix3d(s1.R_w_b.transpose() * truth.R_w_b)).norm(), 1e-6);
  EXPECT_LT((s1.v_w_b_mps - truth.v_w_b_mps).norm(), 1e-6);
  EXPECT_LT((s1.p_w_b_m - truth.p_w_b_m).norm(), 1e-6);
}

TEST(Window, EndsAreCutExactlyBetweenSamples) {
  const Vector3d w(0.1, -0.4, 0.9), a(0.3, 0.2, 9.7);
  std::vector<ImuSample> samples;
  for (int k = 0; k < 50; ++k) samples.push_back(make_sample(k * 5'000'000LL, w, a));
  Preintegrator pi(IntegrationScheme::kMidpoint, ImuNoise{});
  const std::int64_t t0 = 12'345'678, t1 = 201'000'001;
  ASSERT_TRUE(preintegrate_window(samples, t0, t1, Vector3d::Zero(), Vector3d::Zero(), pi));
  EXPECT_EQ(pi.t_start_ns(), t0);
  EXPECT_EQ(pi.t_end_ns(), t1);
  const double T = 1e-9 * static_cast<double>(t1 - t0);
  EXPECT_DOUBLE_EQ(pi.dt_s(), T);
  EXPECT_LT((pi.delta().R - geometry::so3_exp<double>(Vector3d(w * T))).norm(), 1e-12);
  // Not covered: refused.
  EXPECT_FALSE(preintegrate_window(samples, -1, t1, Vector3d::Zero(), Vector3d::Zero(), pi));
  EXPECT_FALSE(
      preintegrate_window(samples, t0, 245'000'001, Vector3d::Zero(), Vector3d::Zero(), pi));
  // Older samples are refused without changing the state.
  Preintegrator p2(IntegrationScheme::kMidpoint, ImuNoise{});
  p2.reset(samples[3], Vector3d::Zero(), Vector3d::Zero());
  EXPECT_FALSE(p2.integrate(samples[2]));
  EXPECT_EQ(p2.steps(), 0);
}

TEST(Covariance, MatchesMonteCarloSpread) {
  // White noise at the densities, 200 Hz, 0.5 s of the synthetic motion; the sample
  // covariance of the increments over 400 runs matches the propagated one (block traces).
  const ImuNoise noise{2e-3, 3e-2};  // large so that the spread dwarfs discretisation
  const double rate = 200.0, dt = 1.0 / rate;
  SyntheticMotion motion;
  std::vector<ImuSample> clean;
  for (int k = 0; k <= 100; ++k) {
    clean.push_back(motion.sample(k * 5'000'000LL, Vector3d(0, 0, -9.81)));
  }
  for (auto scheme : {IntegrationScheme::kMidpoint, IntegrationScheme::kZeroOrderHold}) {
    Preintegrator ref(scheme, noise);
    ASSERT_TRUE(
        preintegrate_window(clean, 0, clean.back().t_ns, Vector3d::Zero(), Vector3d::Zero(), ref));
    std::mt19937 rng(11);
    std::normal_distribution<double> n01(0.0, 1.0);
    Eigen::Matrix<double, 9, 9> S = Eigen::Matrix<double, 9, 9>::Zero();
    const int runs = 400;
    for (int run = 0; run < runs; ++run) {
      // Per-sample white noise of variance density^2 / dt. The midpoint scheme averages
      // neighbouring readings, but each reading still enters the window sum with total
      // weight one, so the integrated spread matches the same model.
      std::vector<ImuSample> noisy = clean;
      const double sg = noise.gyro_noise_density / std::sqrt(dt);
      const double sa = noise.accel_noise_density / std::sqrt(dt);
      for (auto& s : noisy) {
        for (int k = 0; k < 3; ++k) {
          s.gyro_rps[k] += sg * n01(rng);
          s.accel_mps2[k] += sa * n01(rng);
        }
      }
      Preintegrator pi(scheme, noise);
      ASSERT_TRUE(
          preintegrate_window(noisy, 0, clean.back().t_ns, Vector3d::Zero(), Vector3d::Zero(), pi));
      Eigen::Matrix<double, 9, 1> e;
      e.head<3>() = geometry::so3_log<double>(Matrix3d(ref.delta().R.transpose() * pi.delta().R));
      e.segment<3>(3) = pi.delta().v_mps - ref.delta().v_mps;
      e.tail<3>() = pi.delta().p_m - ref.delta().p_m;
      S += e * e.transpose() / runs;
    }
    const auto& C = ref.covariance();
    EXPECT_LT((C - C.transpose()).norm(), 1e-12 * C.norm());
    for (int b = 0; b < 3; ++b) {
      const double predicted = C.block<3, 3>(3 * b, 3 * b).trace();
      const double measured = S.block<3, 3>(3 * b, 3 * b).trace();
      EXPECT_GT(measured / predicted, 0.75) << integration_scheme_name(scheme) << " block " << b;
      EXPECT_LT(measured / predicted, 1.3) << integration_scheme_name(scheme) << " block " << b;
    }
  }
}

TEST(So3Integrals, MatchQuadratureAndNumericDerivativesOnBothBranches) {
  const Vector3d a(0.3, -1.2, 9.6);
  for (double theta : {1e-3, 0.15, 0.199999, 0.200001, 0.6, 2.5}) {
    const Vector3d phi = theta * Vector3d(0.48, -0.6, 0.64);
    // Simpson quadrature of int_0^1 Exp(s phi) ds and int_0^1 (1 - s) Exp(s phi) ds (= Q).
    const int n = 2000;
    Matrix3d L = Matrix3d::Zero(), Q = Matrix3d::Zero();
    for (int k = 0; k <= n; ++k) {
      const double s = static_cast<double>(k) / n;
      const double w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
      const Matrix3d E = geometry::so3_exp<double>(Vector3d(s * phi));
      L += w * E / (3.0 * n);
      Q += w * (1.0 - s) * E / (3.0 * n);
    }
    EXPECT_LT((so3_first_integral(phi).matrix(phi) - L).norm(), 1e-12) << theta;
    EXPECT_LT((so3_second_integral(phi).matrix(phi) - Q).norm(), 1e-12) << theta;
    EXPECT_LT((so3_first_integral(phi).apply(phi, a) - L * a).norm(), 1e-11) << theta;
    for (const auto& f : {so3_first_integral, so3_second_integral}) {
      Matrix3d numeric;
      const double h = 1e-6;
      for (int c = 0; c < 3; ++c) {
        Vector3d d = Vector3d::Zero();
        d[c] = h;
        numeric.col(c) = (f(phi + d).apply(phi + d, a) - f(phi - d).apply(phi - d, a)) / (2 * h);
      }
      EXPECT_LT((f(phi).derivative(phi, a) - numeric).norm(), 1e-7) << theta;
    }
  }
}

TEST(SyntheticMotion, RatesAndForcesAreConsistent) {
  // The analytic body rate matches the numeric derivative of R; velocity that of p.
  SyntheticMotion m;
  for (double t : {0.0, 0.7, 2.3}) {
    const double h = 1e-5;
    const MotionPoint a = m.at(t - h), b = m.at(t + h), c = m.at(t);
    const Vector3d w_num =
        geometry::so3_log<double>(Matrix3d(a.R_w_b.transpose() * b.R_w_b)) / (2 * h);
    EXPECT_LT((w_num - c.omega_b_rps).norm(), 1e-6);
    EXPECT_LT(((b.p_w_b_m - a.p_w_b_m) / (2 * h) - c.v_w_b_mps).norm(), 1e-6);
    EXPECT_LT(((b.v_w_b_mps - a.v_w_b_mps) / (2 * h) - c.a_w_mps2).norm(), 1e-6);
  }
}

}  // namespace
}  // namespace vigs::inertial
