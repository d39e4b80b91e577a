#include <gtest/gtest.h>

#include <cmath>

#include "core/geometry/so3.hpp"
#include "eval/ate.hpp"
#include "eval/rpe.hpp"
#include "eval/trajectory_file.hpp"

namespace vigs::eval {
namespace {

const std::string kDir = std::string(VIGS_SHARED_DATA_DIR) + "/trajectories/";

// Published in ../shared/data/README.md (evo_ape --align on KITTI_00, ORB-SLAM2).
TEST(Ate, ReproducesPublishedKitti00OrbFigures) {
  const auto gt = load_trajectory_file(kDir + "KITTI_00_gt.txt");
  const auto est = load_trajectory_file(kDir + "KITTI_00_ORB.txt");
  EXPECT_EQ(gt.format, TrajectoryFormat::kKitti);
  AteOptions opt;
  opt.align = Alignment::kSe3;
  const AteResult r = compute_ate(gt, est, opt);
  EXPECT_EQ(r.pairs, 4541u);  // no timestamps: index i pairs with index i
  EXPECT_NEAR(r.stats.rmse, 1.3034497145650266, 1e-9);
  EXPECT_NEAR(r.stats.mean, 1.1569971285, 1e-9);
  EXPECT_NEAR(r.stats.median, 1.0656247696, 1e-9);
  EXPECT_NEAR(r.stats.max, 3.5879491207, 1e-9);
  EXPECT_NEAR(r.stats.sse, r.stats.rmse * r.stats.rmse * 4541.0, 1e-6);
  // RMSE is the root mean square, which is never below the mean.
  EXPECT_GT(r.stats.rmse, r.stats.mean);
}

// TUM fr2_desk with ORB-SLAM2: our own figures, recorded when the association was written
// (greedy unique matching as TUM's evaluate_ate.py). They must stay stable.
TEST(Ate, Fr2DeskAssociationAndFiguresAreStable) {
  const auto gt = load_trajectory_file(kDir + "fr2_desk_groundtruth.txt");
  const auto est = load_trajectory_file(kDir + "fr2_desk_ORB.txt");
  EXPECT_EQ(gt.poses.size(), 20957u);
  EXPECT_EQ(est.poses.size(), 2893u);
  AteOptions opt;
  opt.max_dt_s = 0.02;
  const AteResult r = compute_ate(gt, est, opt);
  EXPECT_EQ(r.pairs, 2223u);
  EXPECT_NEAR(r.stats.rmse, 0.0081439671695191888, 1e-12);
  EXPECT_NEAR(r.stats.max, 0.024328989378904931, 1e-12);
  opt.max_dt_s = 0.01;
  const AteResult r10 = compute_ate(gt, est, opt);
  EXPECT_EQ(r10.pairs, 2174u);
  EXPECT_NEAR(r10.stats.rmse, 0.0081189775620454513, 1e-12);
  opt.max_dt_s = 0.02;
  opt.align = Alignment::kSim3;
  const AteResult s = compute_ate(gt, est, opt);
  EXPECT_NEAR(s.alignment.s, 0.99700228840616911, 1e-12);
  EXPECT_LT(s.stats.rmse, r.stats.rmse);
}

Trajectory helix(double scale, const geometry::Pose& T, double t0) {
  Trajectory traj;
  traj.source = "helix";
  for (int i = 0; i < 300; ++i) {
    const double a = 0.05 * i;
    const Eigen::Vector3d p(std::cos(a) * 3.0, std::sin(a) * 2.0, 0.02 * i);
    geometry::Pose P = geometry::make_pose(Eigen::Vector3d(0.1 * std::sin(a), 0.0, a), p);
    P.translation() *= scale;
    traj.poses.push_back({t0 + 0.1 * i, T * P});
  }
  return traj;
}

TEST(Ate, AlignmentModesOnSyntheticDataWithKnownTransformAndScale) {
  const geometry::Pose T =
      geometry::make_pose(Eigen::Vector3d(0.3, -0.2, 1.4), Eigen::Vector3d(5.0, -2.0, 1.0));
  const Trajectory gt = helix(1.0, geometry::Pose::Identity(), 100.0);
  AteOptions opt;
  // Rigidly moved copy: se3 and sim3 give ~0; none gives the offset.
  const Trajectory moved = helix(1.0, T, 100.0);
  opt.align = Alignment::kSe3;
  EXPECT_LT(compute_ate(gt, moved, opt).stats.max, 1e-9);
  opt.align = Alignment::kNone;
  EXPECT_GT(compute_ate(gt, moved, opt).stats.min, 1.0);
  // Scaled copy (x0.5): only sim3 removes the error, and finds the scale 2.
  const Trajectory scaled = helix(0.5, T, 100.0);
  opt.align = Alignment::kSim3;
  const AteResult s = compute_ate(gt, scaled, opt);
  EXPECT_LT(s.stats.max, 1e-9);
  EXPECT_NEAR(s.alignment.s, 2.0, 1e-9);
  opt.align = Alignment::kSe3;
  EXPECT_GT(compute_ate(gt, scaled, opt).stats.rmse, 0.1);
  // Estimate stamped 5 ms late: still associates within 20 ms.
  const Trajectory late = helix(1.0, T, 100.005);
  EXPECT_EQ(compute_ate(gt, late, opt).pairs, 300u);
  // Disjoint stamps: a clear error, not a crash.
  EXPECT_THROW(compute_ate(gt, helix(1.0, T, 500.0), opt), std::invalid_argument);
}

TEST(Rpe, ZeroForRigidlyMovedCopyAndDetectsAScaleError) {
  const geometry::Pose T =
      geometry::make_pose(Eigen::Vector3d(0.3, -0.2, 1.4), Eigen::Vector3d(5.0, -2.0, 1.0));
  const Trajectory gt = helix(1.0, geometry::Pose::Identity(), 0.0);
  RpeOptions opt;
  opt.delta = 10;
  const RpeResult r = compute_rpe(gt, helix(1.0, T, 0.0), opt);
  EXPECT_EQ(r.pairs, 290u);
  EXPECT_LT(r.translation_m.max, 1e-9);
  EXPECT_LT(r.rotation_deg.max, 1e-6);
  const RpeResult s = compute_rpe(gt, helix(0.5, T, 0.0), opt);
  EXPECT_GT(s.translation_m.mean, 0.1);
  EXPECT_LT(s.rotation_deg.max, 1e-6);  // scale does not change relative rotation
  opt.align = Alignment::kSim3;
  EXPECT_LT(compute_rpe(gt, helix(0.5, T, 0.0), opt).translation_m.max, 1e-9);
  // Delta in metres: each pair spans at least 1 m of ground-truth path.
  RpeOptions m;
  m.unit = DeltaUnit::kMetres;
  m.delta = 1.0;
  const RpeResult rm = compute_rpe(gt, helix(1.0, T, 0.0), m);
  EXPECT_GT(rm.pairs, 200u);
  EXPECT_LT(rm.translation_m.max, 1e-9);
  m.delta = 1e6;
  EXPECT_THROW(compute_rpe(gt, gt, m), std::invalid_argument);
  // Delta in seconds: poses are 0.1 s apart, so 1.0 s is 10 frames (up to rounding of the
  // stamps: the first pose at least 1 s later).
  RpeOptions sec;
  sec.unit = DeltaUnit::kSeconds;
  sec.delta = 0.95;
  const RpeResult rs = compute_rpe(gt, helix(0.5, T, 0.0), sec);
  opt.align = Alignment::kNone;
  const RpeResult rf = compute_rpe(gt, helix(0.5, T, 0.0), opt);
  EXPECT_EQ(rs.pairs, rf.pairs);
  EXPECT_DOUBLE_EQ(rs.translation_m.rmse, rf.translation_m.rmse);
}

}  // namespace
}  // namespace vigs::eval
