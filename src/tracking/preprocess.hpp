#pragma once
// One RGB-D frame to a GaussianCloud ready for GICP: points (depth_to_points.hpp), a kd-tree
// over them, and kNN covariances (covariance.hpp). The tree stays valid for the cloud, so the
// frame can serve as a GICP target (CloudTarget) as well as a source.
#include "tracking/covariance.hpp"
#include "tracking/depth_to_points.hpp"
#include "tracking/fork_join.hpp"
#include "tracking/kdtree.hpp"

namespace vigs::tracking {

class FramePreprocessor {
 public:
  struct Setting {
    DepthToPoints::Setting depth;
    CovarianceSetting covariance;
    KdTree::Setting tree;
  };

  /// `team` is shared with the caller's other parallel work and must outlive this object.
  FramePreprocessor(const PinholeCamera& camera, const Setting& setting, ForkJoin& team)
      : depth_(camera, setting.depth), setting_(setting), team_(&team) {}

  /// Depth in metres; `rgb` empty or 3-channel of the same size. `tree` is rebuilt over out.
  DepthToPointsStats process(const io::ImageF32& depth_m, const io::ImageU8& rgb,
                             GaussianCloud& out, KdTree& tree) {
    const DepthToPointsStats stats = depth_.convert(depth_m, rgb, out);
    finish(out, tree);
    return stats;
  }

  /// Covariances for points already in `cloud.points_m` (e.g. loaded from a file).
  void finish(GaussianCloud& cloud, KdTree& tree) const {
    tree.build(cloud.points_m, team_);
    estimate_covariances(tree, setting_.covariance, *team_, cloud);
  }

  [[nodiscard]] const Setting& setting() const { return setting_; }

 private:
  DepthToPoints depth_;
  Setting setting_;
  ForkJoin* team_;
};

}  // namespace vigs::tracking
