// MapLoopCorrection (map_loop_correction.hpp), the part the live mapper and the lockstep replay
// share: on a synthetic room route that returns to its start with drift, each keyframe's
// Gaussians end where the loop closer's final solution puts that keyframe, and without it they
// stay where the drifted odometry put them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "../tracking/synthetic_scene.hpp"
#include "mapping/mapper.hpp"
#include "pipeline/map_loop_correction.hpp"
#include "rt/worker_team.hpp"
#include "tracking/covariance.hpp"
#include "tracking/kdtree.hpp"
#include "tracking/loop_closure.hpp"

namespace vigs::pipeline {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr std::int64_t kSecond = 1'000'000'000;
/// Keyframe k's one Gaussian, in its camera frame (apart for each, so that none is skipped as
/// already in the map).
Eigen::Vector3d point_c(int k) {
  return {0.1, -0.2 + 0.03 * k, 1.5};
}

tracking::Keyframe keyframe_of(const std::vector<Eigen::Vector3f>& world,
                               const geometry::Pose& T_w_c_true,
                               const geometry::Pose& T_w_c_estimate, std::int64_t t_ns) {
  tracking::Keyframe kf;
  kf.t_ns = t_ns;
  kf.T_w_c = T_w_c_estimate;
  const geometry::Pose T_c_w = T_w_c_true.inverse();
  for (const Eigen::Vector3f& p : world) {
    const Eigen::Vector3f q = (T_c_w * p.cast<double>()).cast<float>();
    if (q.z() > 0.5f) kf.cloud_c.points_m.push_back(q);
  }
  kf.cloud_c.colors_rgb.assign(kf.cloud_c.size(), {0, 0, 0});
  tracking::KdTree tree;
  tree.build(kf.cloud_c.points_m);
  rt::WorkerTeam team(2);
  tracking::estimate_covariances(tree, tracking::CovarianceSetting{}, team, kf.cloud_c);
  kf.moving.assign(kf.cloud_c.size(), 0);
  return kf;
}

/// One Gaussian at point_c(id) in front of a keyframe placed at T_w_c (no view: nothing trains).
std::unique_ptr<mapping::MapperKeyframe> map_keyframe(std::uint64_t id,
                                                      const geometry::Pose& T_w_c) {
  auto m = std::make_unique<mapping::MapperKeyframe>();
  m->id = id;
  m->gaussians.T_w_c = T_w_c;
  m->gaussians.points_c.push_back(point_c(static_cast<int>(id)).cast<float>());
  m->gaussians.covariances_c.push_back(Eigen::Matrix3f::Identity() * 1e-4f);
  m->gaussians.colors.emplace_back(0.5f, 0.5f, 0.5f);
  return m;
}

struct Outcome {
  std::vector<Eigen::Vector3d> gaussian_w;  ///< by keyframe id
  std::vector<Eigen::Vector3d> solved_w;    ///< point_c(k) at keyframe k's final solved pose
  std::int64_t closures = 0;
};

Outcome run(bool follow) {
  const auto world = tracking::test::room_scene(40000);
  config::GicpSetting gicp;
  gicp.max_correspondence_distance_m = 0.05;
  gicp.kernel = config::RobustKernel::geman_mcclure;
  tracking::LoopCloser::Setting ls;
  ls.enabled = true;
  ls.min_age_s = 5.0;
  ls.anchor_spacing_m = 0.2;
  tracking::LoopCloser loops(ls, gicp);
  config::MappingSettings ms;
  ms.iterations_per_tick = 0;  // insertion only
  ms.far_field.depth_m = 0.0;
  ms.insert.voxel_m = 0.001;
  mapping::KeyframeRing ring(4);
  mapping::Mapper mapper(ms, ring, nullptr, 4, 64);
  MapLoopCorrection correction;
  // out 1.2 m and back, one keyframe a second; the odometry drifts 1 cm and 0.4 deg of yaw each
  const int n = 12;
  geometry::Pose est = geometry::Pose::Identity(), prev_truth = geometry::Pose::Identity();
  for (int k = 0; k <= n; ++k) {
    const double x = 1.2 * (k <= n / 2 ? k : n - k) / (n / 2);
    const geometry::Pose truth =
        geometry::make_pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(x, 0, 0));
    if (k > 0)
      est = est * prev_truth.inverse() * truth *
            geometry::make_pose(Eigen::Vector3d(0, 0.4 * kDeg, 0), Eigen::Vector3d(0.01, 0, 0));
    prev_truth = truth;
    const bool closed =
        loops.add_keyframe(keyframe_of(world, truth, est, static_cast<std::int64_t>(k) * kSecond));
    const geometry::Pose T_map = follow ? correction.place(loops, k) : est;
    EXPECT_TRUE(ring.try_push(map_keyframe(static_cast<std::uint64_t>(k), T_map)));
    mapper.tick();
    if (closed && follow) correction.apply(loops, mapper);
  }
  loops.optimize();
  if (follow) correction.apply(loops, mapper);
  Outcome r;
  r.closures = loops.stats().closures;
  const auto& map = mapper.map();
  EXPECT_EQ(map.size(), static_cast<std::size_t>(n + 1));
  r.gaussian_w.resize(map.size());
  for (std::size_t i = 0; i < map.size(); ++i)
    r.gaussian_w[mapper.anchors()[i]] =
        Eigen::Vector3d(map.mean_w[3 * i], map.mean_w[3 * i + 1], map.mean_w[3 * i + 2]);
  for (int k = 0; k <= n; ++k) r.solved_w.push_back(loops.graph().pose(k) * point_c(k));
  return r;
}

TEST(MapLoopCorrection, EachKeyframesGaussiansEndAtItsSolvedPose) {
  const Outcome on = run(true);
  const Outcome off = run(false);
  ASSERT_GE(on.closures, 1);
  double worst_on = 0.0, worst_off = 0.0;
  for (std::size_t k = 0; k < on.solved_w.size(); ++k) {
    worst_on = std::max(worst_on, (on.gaussian_w[k] - on.solved_w[k]).norm());
    worst_off = std::max(worst_off, (off.gaussian_w[k] - on.solved_w[k]).norm());
  }
  std::printf("largest distance to the solved keyframe poses: %.4f m following, %.4f m not\n",
              worst_on, worst_off);
  // within the corrections left to accumulate (2 mm and 0.02 deg at 1.5 m: 2.5 mm)
  EXPECT_LT(worst_on, 3e-3);
  EXPECT_GT(worst_off, 0.03);  // the odometry's drift, which the map kept before
}

}  // namespace
}  // namespace vigs::pipeline
