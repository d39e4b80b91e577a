#pragma once
// A drifted out-and-back route through the synthetic room (synthetic_scene.hpp), for the tests
// of the loop closer and of what follows it (pipeline's MapLoopCorrection): the keyframe a
// camera at a true pose sees, carrying a drifted estimate, and the loop closer's settings.
#include <cstdint>
#include <vector>

#include "core/geometry/se3.hpp"
#include "rt/worker_team.hpp"
#include "synthetic_scene.hpp"
#include "tracking/covariance.hpp"
#include "tracking/gaussian_cloud.hpp"
#include "tracking/kdtree.hpp"
#include "tracking/loop_closure.hpp"

namespace vigs::tracking::test {

inline constexpr double kDeg = 3.14159265358979323846 / 180.0;
inline constexpr std::int64_t kSecond = 1'000'000'000;

/// The world points a camera at T_w_c sees in front of it, in its frame, with covariances.
inline Keyframe keyframe_of(const std::vector<Eigen::Vector3f>& world,
                            const geometry::Pose& T_w_c_true, const geometry::Pose& T_w_c_estimate,
                            std::int64_t t_ns) {
  Keyframe kf;
  kf.t_ns = t_ns;
  kf.T_w_c = T_w_c_estimate;
  const geometry::Pose T_c_w = T_w_c_true.inverse();
  for (const Eigen::Vector3f& p : world) {
    const Eigen::Vector3f q = (T_c_w * p.cast<double>()).cast<float>();
    if (q.z() > 0.5f) kf.cloud_c.points_m.push_back(q);
  }
  kf.cloud_c.colors_rgb.assign(kf.cloud_c.size(), {0, 0, 0});
  KdTree tree;
  tree.build(kf.cloud_c.points_m);
  rt::WorkerTeam team(2);
  estimate_covariances(tree, CovarianceSetting{}, team, kf.cloud_c);
  kf.moving.assign(kf.cloud_c.size(), 0);
  return kf;
}

inline config::GicpSetting tracker_gicp() {
  config::GicpSetting g;
  g.max_correspondence_distance_m = 0.05;
  g.kernel = config::RobustKernel::geman_mcclure;
  return g;
}

inline LoopCloser::Setting loop_setting() {
  LoopCloser::Setting s;
  s.enabled = true;
  s.min_age_s = 5.0;
  s.anchor_spacing_m = 0.2;
  return s;
}

/// Out 1.2 m sideways and back, one keyframe a second; the estimate drifts 1 cm and 0.4
/// degrees of yaw a keyframe.
struct Route {
  std::vector<geometry::Pose> truth, estimate;
};
inline Route out_and_back() {
  Route r;
  geometry::Pose est = geometry::Pose::Identity();
  const int n = 12;
  for (int k = 0; k <= n; ++k) {
    const double x = 1.2 * (k <= n / 2 ? k : n - k) / (n / 2);
    r.truth.push_back(geometry::make_pose(Eigen::Vector3d::Zero(), Eigen::Vector3d(x, 0, 0)));
    if (k > 0) {
      const geometry::Pose step = r.truth[k - 1].inverse() * r.truth[k];
      est = est * step *
            geometry::make_pose(Eigen::Vector3d(0, 0.4 * kDeg, 0), Eigen::Vector3d(0.01, 0, 0));
    }
    r.estimate.push_back(est);
  }
  return r;
}

}  // namespace vigs::tracking::test
