// The frontend's per-frame calls do not allocate after construction (the tracker thread is
// real-time), and the gravity alignment of the initial attitude.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <new>
#include <vector>

#include "core/config/extrinsics_settings.hpp"
#include "core/config/imu_settings.hpp"
#include "core/config/inertial_settings.hpp"
#include "core/geometry/so3.hpp"
#include "inertial/gravity_alignment.hpp"
#include "inertial/inertial_frontend.hpp"
#include "inertial/synthetic_motion.hpp"

namespace {
std::atomic<long> g_allocations{0};
}  // namespace

// Count every global allocation made by this test program.
void* operator new(std::size_t n) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace vigs::inertial {
namespace {

using Eigen::Vector3d;

TEST(Realtime, FrameCallsDoNotAllocateAfterConstruction) {
  const SyntheticMotion motion;
  const auto opts = InertialFrontendOptions::from(
      config::ImuSettings{}, config::ExtrinsicsSettings{}, config::InertialSettings{});
  const long at_start = g_allocations.load();
  InertialFrontend f(opts);
  ASSERT_GT(g_allocations.load(), at_start);  // the counter sees the ring's allocation
  const Vector3d g(0, 0, -9.81);
  std::int64_t next = 0;
  long during = 0;
  bool all_predicted = true;
  for (int k = 0; k < 40; ++k) {
    const std::int64_t t = 1'000'000 + k * 50'000'000LL;
    const MotionPoint m = motion.at(1e-9 * static_cast<double>(t));
    geometry::Pose T_w_b = geometry::Pose::Identity();
    T_w_b.linear() = m.R_w_b;
    T_w_b.translation() = m.p_w_b_m;
    const long before = g_allocations.load();
    while (next <= t + 10'000'000) {
      f.add_sample(motion.sample(next, g));
      next += 5'000'000;
    }
    const auto guess = f.predict_camera_pose(t);
    f.reset_from_tracked(t, T_w_b * opts.T_b_c);
    during += g_allocations.load() - before;
    all_predicted = all_predicted && (k == 0 || guess.has_value());
  }
  EXPECT_EQ(during, 0);
  EXPECT_TRUE(all_predicted);
  EXPECT_GT(f.bias_estimator().updates(), 30);
}

TEST(GravityAlignment, LevelsTheBodyFromAccelerometerAtRest) {
  const Eigen::Matrix3d R_true = geometry::so3_exp<double>(Vector3d(0.3, -0.2, 0.0));
  const Vector3d f_b = R_true.transpose() * Vector3d(0, 0, 9.81);
  const auto R = gravity_aligned_R_w_b(f_b);
  ASSERT_TRUE(R.has_value());
  EXPECT_LT((*R * f_b - Vector3d(0, 0, 9.81)).norm(), 1e-12);
  EXPECT_NEAR(R->determinant(), 1.0, 1e-12);
  EXPECT_FALSE(gravity_aligned_R_w_b(Vector3d::Zero()).has_value());
  ImuSample s;
  for (int k = 0; k < 3; ++k) s.accel_mps2[k] = f_b[k];
  const ImuSample two[2] = {s, s};
  EXPECT_LT((*gravity_aligned_R_w_b(std::span<const ImuSample>(two), 0) - *R).norm(), 1e-12);
  EXPECT_FALSE(gravity_aligned_R_w_b(std::span<const ImuSample>(), 0).has_value());
}

TEST(GravityAlignment, TheGyroCarriesASwayingWindowBackToTheReferenceFrame) {
  // At rest in position, the body sways about x and z at a constant rate: every reading in the
  // window sees gravity from another attitude. Referred to the attitude at t_ref by the gyro,
  // they agree exactly; their plain mean is tilted by half the window's rotation.
  const Vector3d w_rps(0.2, 0.0, 0.1);
  const Eigen::Matrix3d R_w_b0 = geometry::so3_exp<double>(Vector3d(0.05, -0.1, 0.0));
  constexpr std::int64_t kDtNs = 5'000'000;
  std::vector<ImuSample> samples(100);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Eigen::Matrix3d R_w_b =
        R_w_b0 * geometry::so3_exp<double>(Vector3d(w_rps * 0.005 * static_cast<double>(i)));
    const Vector3d f_b = R_w_b.transpose() * Vector3d(0, 0, 9.81);
    samples[i].t_ns = static_cast<std::int64_t>(i) * kDtNs;
    for (int k = 0; k < 3; ++k) {
      samples[i].gyro_rps[k] = w_rps[k];
      samples[i].accel_mps2[k] = f_b[k];
    }
  }
  const auto tilt_rad = [](const Eigen::Matrix3d& R_est, const Eigen::Matrix3d& R_true) {
    const Vector3d up_est = R_est.transpose() * Vector3d::UnitZ();  // world up in the body
    const Vector3d up_true = R_true.transpose() * Vector3d::UnitZ();
    return std::atan2(up_est.cross(up_true).norm(), up_est.dot(up_true));
  };
  for (const std::size_t ref : {std::size_t{0}, std::size_t{40}, std::size_t{99}}) {
    SCOPED_TRACE(ref);
    const Eigen::Matrix3d R_true =
        R_w_b0 * geometry::so3_exp<double>(Vector3d(w_rps * 0.005 * static_cast<double>(ref)));
    const auto R = gravity_aligned_R_w_b(std::span<const ImuSample>(samples),
                                         static_cast<std::int64_t>(ref) * kDtNs + 1'000'000);
    ASSERT_TRUE(R.has_value());
    EXPECT_LT(tilt_rad(*R, R_true), 1e-9);
  }
  Vector3d mean = Vector3d::Zero();
  for (const ImuSample& s : samples)
    mean += Vector3d(s.accel_mps2[0], s.accel_mps2[1], s.accel_mps2[2]);
  EXPECT_GT(tilt_rad(*gravity_aligned_R_w_b(Vector3d(mean / 100.0)), R_w_b0), 0.03);
}

}  // namespace
}  // namespace vigs::inertial
