// The loop closer on keyframes of a synthetic room: a drifted return to the first keyframe's
// place is registered, verified and corrected; a place that does not match is refused; and
// nothing is corrected while no old keyframe is near.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "drifted_route.hpp"
#include "tracking/loop_closure.hpp"

namespace vigs::tracking {
namespace {

using test::keyframe_of;
using test::kSecond;
using test::loop_setting;
using test::out_and_back;
using test::plane_scene;
using test::room_scene;
using test::Route;
using test::tracker_gicp;

TEST(LoopCloser, ClosesADriftedReturnAndCorrectsTheTrajectory) {
  const auto world = room_scene(40000);
  const Route r = out_and_back();
  LoopCloser lc(loop_setting(), tracker_gicp());
  int closed_at = -1;
  for (std::size_t k = 0; k < r.truth.size(); ++k) {
    const bool closed = lc.add_keyframe(
        keyframe_of(world, r.truth[k], r.estimate[k], static_cast<std::int64_t>(k) * kSecond));
    if (closed && closed_at < 0) closed_at = static_cast<int>(k);
  }
  ASSERT_GE(closed_at, 0) << "no loop closed";
  EXPECT_GE(lc.stats().closures, 1);
  EXPECT_EQ(lc.stats().keyframes, static_cast<std::int64_t>(r.truth.size()));
  lc.optimize();

  // The last keyframe's estimate is off by the route's drift; corrected, it is back.
  const std::size_t last = r.truth.size() - 1;
  const auto t_last = static_cast<std::int64_t>(last) * kSecond;
  const double raw = (r.estimate[last].translation() - r.truth[last].translation()).norm();
  const geometry::Pose fixed = lc.corrected(t_last, r.estimate[last]);
  const double err = (fixed.translation() - r.truth[last].translation()).norm();
  const double yaw_raw =
      Eigen::AngleAxisd(r.estimate[last].linear().transpose() * r.truth[last].linear()).angle();
  const double yaw_err =
      Eigen::AngleAxisd(fixed.linear().transpose() * r.truth[last].linear()).angle();
  ASSERT_GT(raw, 0.08);
  EXPECT_LT(err, 0.02) << "raw " << raw << " m";
  EXPECT_LT(yaw_err, 0.25 * yaw_raw);
  // After the last keyframe a pose moves with it; between two keyframes with the correction
  // interpolated between theirs (at the identity a pose is its correction); before the first
  // keyframe nothing moves.
  const geometry::Pose after = lc.corrected(t_last + kSecond / 2, r.estimate[last]);
  EXPECT_TRUE(after.isApprox(fixed, 1e-12));
  const geometry::Pose I = geometry::Pose::Identity();
  const geometry::Pose C_a = lc.corrected(t_last - kSecond, I);
  const geometry::Pose C_b = lc.corrected(t_last, I);
  const geometry::Pose C_mid = lc.corrected(t_last - kSecond / 2, I);
  ASSERT_GT((C_b.translation() - C_a.translation()).norm(), 1e-3);  // the two differ
  EXPECT_LT((C_mid.translation() - 0.5 * (C_a.translation() + C_b.translation())).norm(), 1e-9);
  const double turn = Eigen::AngleAxisd(C_a.linear().transpose() * C_b.linear()).angle();
  EXPECT_NEAR(Eigen::AngleAxisd(C_a.linear().transpose() * C_mid.linear()).angle(), 0.5 * turn,
              1e-9);
  const geometry::Pose before = lc.corrected(-1, r.estimate[last]);
  EXPECT_TRUE(before.isApprox(r.estimate[last], 1e-12));
}

TEST(LoopCloser, NothingIsCorrectedWhileNoOldKeyframeIsNear) {
  const auto world = room_scene(40000);
  const Route r = out_and_back();
  LoopCloser::Setting s = loop_setting();
  s.min_age_s = 100.0;  // the first keyframe is never old enough
  LoopCloser lc(s, tracker_gicp());
  for (std::size_t k = 0; k < r.truth.size(); ++k) {
    EXPECT_FALSE(lc.add_keyframe(
        keyframe_of(world, r.truth[k], r.estimate[k], static_cast<std::int64_t>(k) * kSecond)));
  }
  lc.optimize();
  EXPECT_EQ(lc.stats().attempts, 0);
  const std::size_t last = r.truth.size() - 1;
  EXPECT_TRUE(lc.corrected(static_cast<std::int64_t>(last) * kSecond, r.estimate[last])
                  .isApprox(r.estimate[last], 1e-9));
}

TEST(LoopCloser, RefusesAReturnThatSeesAnotherPlace) {
  const auto world = room_scene(40000);
  const auto elsewhere = plane_scene(40000);  // one wall: nothing of the room
  const Route r = out_and_back();
  LoopCloser lc(loop_setting(), tracker_gicp());
  const std::size_t last = r.truth.size() - 1;
  for (std::size_t k = 0; k <= last; ++k) {
    const auto& scene = k == last ? elsewhere : world;
    const bool closed = lc.add_keyframe(
        keyframe_of(scene, r.truth[k], r.estimate[k], static_cast<std::int64_t>(k) * kSecond));
    if (k == last) {
      EXPECT_FALSE(closed);
    }
  }
  EXPECT_GE(lc.stats().rejected, 1);
}

TEST(LoopCloser, AReturnAlongThePathKeepsNoNewAnchors) {
  const auto world = room_scene(40000);
  const Route r = out_and_back();
  LoopCloser lc(loop_setting(), tracker_gicp());
  std::int64_t anchors_out = 0;
  for (std::size_t k = 0; k < r.truth.size(); ++k) {
    lc.add_keyframe(
        keyframe_of(world, r.truth[k], r.estimate[k], static_cast<std::int64_t>(k) * kSecond));
    if (k == r.truth.size() / 2) anchors_out = lc.stats().anchors;
  }
  // Out 1.2 m in 0.2 m steps (0.21 m estimated): a new place each; the way back sees them again.
  EXPECT_GE(anchors_out, 6);
  EXPECT_EQ(lc.stats().anchors, anchors_out);
  EXPECT_EQ(lc.stats().anchors_dropped, 0);
  EXPECT_GT(lc.stats().closures, 0);
}

TEST(LoopCloser, KeepsItsAnchorsWithinTheMemoryBudget) {
  const auto world = room_scene(40000);
  const auto along = [](int k) {
    return geometry::make_pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.25 * k, 0, 0));
  };
  LoopCloser one(loop_setting(), tracker_gicp());
  one.add_keyframe(keyframe_of(world, along(0), along(0), 0));
  const std::size_t per_anchor = one.stats().anchor_bytes;
  ASSERT_GT(per_anchor, 10000u);

  LoopCloser::Setting s = loop_setting();
  s.max_anchor_mb = 5.5 * static_cast<double>(per_anchor) / (1024.0 * 1024.0);
  LoopCloser lc(s, tracker_gicp());
  for (int k = 0; k < 12; ++k) {
    lc.add_keyframe(keyframe_of(world, along(k), along(k), k * kSecond));
    EXPECT_LE(static_cast<double>(lc.stats().anchor_bytes), s.max_anchor_mb * 1024.0 * 1024.0);
  }
  // 12 places 0.25 m apart, each new: the clouds differ a little with the view, so 4-6 fit.
  EXPECT_GE(lc.stats().anchors, 4);
  EXPECT_LE(lc.stats().anchors, 6);
  EXPECT_EQ(lc.stats().anchors + lc.stats().anchors_dropped, 12);
}

}  // namespace
}  // namespace vigs::tracking
