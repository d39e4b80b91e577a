// The IMU-seeded initial guess: composition of the camera pose, reset from tracked poses,
// velocity from tracked positions, the gyro-bias update and the sample queue.
#include <gtest/gtest.h>

#include <cmath>

#include "core/config/extrinsics_settings.hpp"
#include "core/config/imu_settings.hpp"
#include "core/config/inertial_settings.hpp"
#include "core/geometry/se3.hpp"
#include "inertial/inertial_frontend.hpp"
#include "inertial/synthetic_motion.hpp"

namespace vigs::inertial {
namespace {

using Eigen::Vector3d;
using geometry::Pose;

constexpr std::int64_t kImuPeriodNs = 5'000'000;     // 200 Hz
constexpr std::int64_t kFramePeriodNs = 50'000'000;  // 20 Hz
constexpr std::int64_t kFrameOffsetNs = 12'345'678;  // frames fall between IMU samples
const Vector3d kGravity(0, 0, -9.81);

struct Scenario {
  SyntheticMotion motion;
  Vector3d gyro_bias_rps = Vector3d::Zero();
  InertialFrontendOptions options;
  std::int64_t next_imu_ns = 0;
  std::int64_t imu_clock_offset_ns = 0;  // IMU stamps = motion time + offset

  Scenario() {
    options = InertialFrontendOptions::from(config::ImuSettings{}, config::ExtrinsicsSettings{},
                                            config::InertialSettings{});
  }
  [[nodiscard]] Pose T_w_c(std::int64_t t_ns) const {
    const MotionPoint m = motion.at(1e-9 * static_cast<double>(t_ns));
    Pose T_w_b = Pose::Identity();
    T_w_b.linear() = m.R_w_b;
    T_w_b.translation() = m.p_w_b_m;
    return T_w_b * options.T_b_c;
  }
  // Feeds IMU samples up to t_ns plus two samples of look-ahead (the IMU runs ahead).
  void feed(InertialFrontend& f, std::int64_t t_ns) {
    while (next_imu_ns <= t_ns + 2 * kImuPeriodNs) {
      ImuSample s = motion.sample(next_imu_ns, kGravity);
      s.t_ns += imu_clock_offset_ns;
      for (int k = 0; k < 3; ++k) s.gyro_rps[k] += gyro_bias_rps[k];
      f.add_sample(s);
      next_imu_ns += kImuPeriodNs;
    }
  }
};

std::int64_t frame_time(int k) {
  return kFrameOffsetNs + k * kFramePeriodNs;
}

struct GuessErrors {
  double max_translation_m = 0.0;
  double max_rotation_deg = 0.0;
};

// Tracks `frames` frames with perfect GICP results; returns the guess errors after warm-up.
// Frames [first, first + frames); the first `warmup` of a fresh run are not scored.
GuessErrors run(Scenario& sc, InertialFrontend& f, int frames, int warmup = 3, int first = 0) {
  GuessErrors e;
  for (int k = first; k < first + frames; ++k) {
    const std::int64_t t = frame_time(k);
    sc.feed(f, t);
    const auto guess = f.predict_camera_pose(t);
    EXPECT_EQ(guess.has_value(), k > 0) << k;
    if (guess && k >= warmup) {
      const auto err = geometry::pose_error(*guess, sc.T_w_c(t));
      e.max_translation_m = std::max(e.max_translation_m, err.translation_m);
      e.max_rotation_deg = std::max(e.max_rotation_deg, err.rotation_rad * 180.0 / M_PI);
    }
    EXPECT_TRUE(f.reset_from_tracked(t, sc.T_w_c(t)));
  }
  return e;
}

TEST(InertialFrontend, GuessFollowsTheMotionWithImuCorrectedVelocity) {
  Scenario sc;
  sc.options.velocity_reset = VelocityReset::kImu;
  sc.options.estimate_gyro_bias = false;
  InertialFrontend f(sc.options);
  const GuessErrors e = run(sc, f, 100);
  EXPECT_LT(e.max_translation_m, 2e-5);
  EXPECT_LT(e.max_rotation_deg, 1e-3);
  EXPECT_EQ(f.counters().resets, 100);
  EXPECT_EQ(f.counters().extrapolated, 0);
}

TEST(InertialFrontend, ImuClockOffsetIsApplied) {
  Scenario sc;
  sc.options.velocity_reset = VelocityReset::kImu;
  sc.imu_clock_offset_ns = 20'000'000;
  sc.options.time_offset_ns = 20'000'000;
  InertialFrontend f(sc.options);
  EXPECT_LT(run(sc, f, 40).max_translation_m, 2e-5);
  Scenario wrong = sc;  // offset ignored: visibly worse
  wrong.next_imu_ns = 0;
  wrong.options.time_offset_ns = 0;
  InertialFrontend g(wrong.options);
  EXPECT_GT(run(wrong, g, 40).max_translation_m, 1e-4);
}

TEST(InertialFrontend, PaperVelocityResetLagsByHalfAFrameButStaysClose) {
  Scenario sc;
  sc.options.estimate_gyro_bias = false;
  InertialFrontend f(sc.options);
  const GuessErrors e = run(sc, f, 100);
  // v = dp/dt is the mean velocity over the last interval, late by dt/2: the guess is off by
  // about |a| dt^2 / 2, here up to ~2 mm for |a| <= 1.8 m/s^2 at 20 Hz.
  EXPECT_LT(e.max_translation_m, 3e-3);
  EXPECT_GT(e.max_translation_m, 2e-5);  // and visibly worse than the IMU-corrected reset
  EXPECT_LT(e.max_rotation_deg, 1e-3);
}

// restart() forgets the motion: the next reset starts at rest at its pose, as the first one
// did, keeping the samples (a guess follows at once) and the gyro-bias estimate.
TEST(InertialFrontend, RestartStartsAgainAtRestAtTheNextTrackedPose) {
  Scenario sc;
  InertialFrontend f(sc.options);
  run(sc, f, 20);
  ASSERT_GT(f.velocity_w_mps().norm(), 0.1);  // the synthetic body moves at ~1 m/s
  const Vector3d bias = f.bias_gyro_rps();
  f.restart();
  const std::int64_t t = frame_time(20);
  sc.feed(f, t);
  EXPECT_FALSE(f.predict_camera_pose(t).has_value()) << "no state until the next reset";
  const Pose T_w_c = sc.T_w_c(t) * Pose(Eigen::Translation3d(0.5, 0.0, 0.0));  // anywhere
  ASSERT_TRUE(f.reset_from_tracked(t, T_w_c));
  EXPECT_EQ(f.velocity_w_mps().norm(), 0.0);
  EXPECT_LT(
      geometry::pose_error(f.state_at_reset().T_w_b() * sc.options.T_b_c, T_w_c).translation_m,
      1e-12);
  EXPECT_EQ(f.bias_gyro_rps(), bias);
  EXPECT_EQ(f.counters().restarts, 1);
  sc.feed(f, frame_time(21));
  EXPECT_TRUE(f.predict_camera_pose(frame_time(21)).has_value());
  // Without the restart the same reset keeps the body's velocity (the difference of positions).
  Scenario sc2;
  InertialFrontend g(sc2.options);
  run(sc2, g, 20);
  sc2.feed(g, t);
  ASSERT_TRUE(g.reset_from_tracked(t, T_w_c));
  EXPECT_GT(g.velocity_w_mps().norm(), 1.0);
}

TEST(InertialFrontend, GuessIsThePaperCompositionOfThePredictedBodyMotion) {
  Scenario sc;
  InertialFrontend f(sc.options);
  run(sc, f, 5);
  const std::int64_t t = frame_time(5);
  sc.feed(f, t);
  const Pose T_w_c_prev = sc.T_w_c(frame_time(4));
  const auto s = f.predict_state(t);
  const auto guess = f.predict_camera_pose(t);
  ASSERT_TRUE(s && guess);
  // T_w_c(k) = T_w_c(k-1) T_c_b T_b(k-1 -> k) T_b_c equals T_w_b(k) T_b_c when T_w_c(k-1)
  // was the reset pose.
  const Pose T_rel = f.state_at_reset().T_w_b().inverse() * s->T_w_b();
  const Pose composed = T_w_c_prev * sc.options.T_b_c.inverse() * T_rel * sc.options.T_b_c;
  EXPECT_LT(geometry::pose_error(composed, *guess).translation_m, 1e-12);
  EXPECT_LT(geometry::pose_error(s->T_w_b() * sc.options.T_b_c, *guess).translation_m, 1e-12);
  // Reset R and p are the tracked pose converted to the body frame.
  const Pose T_w_b_prev = T_w_c_prev * sc.options.T_b_c.inverse();
  EXPECT_LT((f.state_at_reset().p_w_b_m - T_w_b_prev.translation()).norm(), 1e-12);
  EXPECT_LT((f.state_at_reset().R_w_b - T_w_b_prev.linear()).norm(), 1e-12);
}

TEST(GyroBias, ConvergesToAConstantBiasFromGicpRotations) {
  const Vector3d true_bias(0.01, -0.02, 0.015);
  Scenario with;
  with.gyro_bias_rps = true_bias;
  with.options.velocity_reset = VelocityReset::kImu;
  InertialFrontend f(with.options);
  run(with, f, 150);  // 7.5 s at gain 0.1 per frame
  EXPECT_LT((f.bias_gyro_rps() - true_bias).norm(), 1e-4) << f.bias_gyro_rps().transpose();
  EXPECT_EQ(f.bias_estimator().gated(), 0);
  // The next 50 guesses are then much better than without the estimate.
  const GuessErrors converged = run(with, f, 50, 0, 150);
  Scenario without = with;
  without.next_imu_ns = 0;
  without.options.estimate_gyro_bias = false;
  InertialFrontend g(without.options);
  run(without, g, 150);
  const GuessErrors uncorrected = run(without, g, 50, 0, 150);
  EXPECT_LT(converged.max_rotation_deg, 0.1 * uncorrected.max_rotation_deg);
  EXPECT_EQ(g.bias_gyro_rps().norm(), 0.0);
}

TEST(GyroBias, OutlierResidualsAreGatedAndStepsClamped) {
  Scenario sc;
  sc.gyro_bias_rps = Vector3d(0.5, 0.0, 0.0);  // far beyond one clamped step
  sc.options.velocity_reset = VelocityReset::kImu;
  InertialFrontend f(sc.options);
  for (int k = 0; k < 3; ++k) {
    const std::int64_t t = frame_time(k);
    sc.feed(f, t);
    f.reset_from_tracked(t, sc.T_w_c(t));
  }
  // Two updates so far, each limited to max_step.
  EXPECT_NEAR(f.bias_gyro_rps().norm(), 2 * sc.options.bias.max_step_rps, 1e-12);
  EXPECT_EQ(f.bias_estimator().clamped(), 2);
  // A 10 deg tracking jump is not bias: skipped.
  const Vector3d before = f.bias_gyro_rps();
  const std::int64_t t = frame_time(3);
  sc.feed(f, t);
  Pose jumped = sc.T_w_c(t);
  jumped.linear() = jumped.linear() * geometry::so3_exp<double>(Vector3d(0.0, 0.0, 0.1745));
  f.reset_from_tracked(t, jumped);
  EXPECT_EQ(f.bias_estimator().gated(), 1);
  EXPECT_EQ((f.bias_gyro_rps() - before).norm(), 0.0);
}

TEST(InertialFrontend, QueueOrderOverflowAndEdgeCases) {
  Scenario sc;
  sc.options.buffer_capacity = 16;
  InertialFrontend f(sc.options);
  EXPECT_FALSE(f.predict_camera_pose(0).has_value());  // nothing tracked yet
  for (int k = 0; k < 20; ++k) {
    EXPECT_TRUE(f.add_sample(sc.motion.sample(k * kImuPeriodNs, kGravity)));
  }
  EXPECT_EQ(f.counters().samples_dropped, 4);
  EXPECT_FALSE(f.add_sample(sc.motion.sample(3 * kImuPeriodNs, kGravity)));
  EXPECT_EQ(f.counters().samples_out_of_order, 1);
  ASSERT_TRUE(f.reset_from_tracked(60'000'000, sc.T_w_c(60'000'000)));
  EXPECT_FALSE(f.reset_from_tracked(50'000'000, sc.T_w_c(50'000'000)));  // before the last
  EXPECT_FALSE(f.predict_camera_pose(50'000'000).has_value());
  // Beyond the newest sample (95 ms): the last reading is held, and counted.
  const auto g = f.predict_camera_pose(110'000'000);
  ASSERT_TRUE(g.has_value());
  EXPECT_EQ(f.counters().extrapolated, 1);
  EXPECT_TRUE(g->matrix().allFinite());
}

}  // namespace
}  // namespace vigs::inertial
