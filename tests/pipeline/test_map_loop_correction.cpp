// MapLoopCorrection (map_loop_correction.hpp), the part the live mapper and the lockstep replay
// share: on a synthetic room route that returns to its start with drift, each keyframe's
// Gaussians end where the loop closer's final solution puts that keyframe
// (LoopCloser::solved), and without it they stay where the drifted odometry put them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "../tracking/drifted_route.hpp"
#include "mapping/mapper.hpp"
#include "pipeline/map_loop_correction.hpp"

namespace vigs::pipeline {
namespace {

/// Keyframe k's one Gaussian, in its camera frame (apart for each, so that none is skipped as
/// already in the map).
Eigen::Vector3d point_c(int k) {
  return {0.1, -0.2 + 0.03 * k, 1.5};
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
  const tracking::test::Route route = tracking::test::out_and_back();
  tracking::LoopCloser loops(tracking::test::loop_setting(), tracking::test::tracker_gicp());
  config::MappingSettings ms;
  ms.iterations_per_tick = 0;  // insertion only
  ms.far_field.depth_m = 0.0;
  ms.insert.voxel_m = 0.001;
  mapping::KeyframeRing ring(4);
  mapping::Mapper mapper(ms, ring, nullptr, 4, 64);
  MapLoopCorrection correction;
  const int n = static_cast<int>(route.truth.size()) - 1;
  for (int k = 0; k <= n; ++k) {
    const auto i = static_cast<std::size_t>(k);
    const bool closed = loops.add_keyframe(tracking::test::keyframe_of(
        world, route.truth[i], route.estimate[i], k * tracking::test::kSecond));
    const geometry::Pose T_map = follow ? correction.place(loops) : route.estimate[i];
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
  for (int k = 0; k <= n; ++k)
    r.solved_w.push_back(loops.solved(static_cast<std::size_t>(k)) * point_c(k));
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
