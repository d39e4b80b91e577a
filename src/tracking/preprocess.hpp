#pragma once
// One RGB-D frame to a GaussianCloud ready for GICP: points (depth_to_points.hpp) and kNN
// covariances (covariance.hpp), the neighbours found through the depth image
// (organized_knn.hpp) or a kd-tree, as CovarianceSetting::knn_search says. A frame that will
// serve as a GICP target (CloudTarget) also gets a kd-tree over its points.
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "rt/worker_team.hpp"
#include "tracking/covariance.hpp"
#include "tracking/depth_to_points.hpp"
#include "tracking/kdtree.hpp"
#include "tracking/organized_knn.hpp"
#include "tracking/pixel_grid.hpp"

namespace vigs::tracking {

class FramePreprocessor {
 public:
  using Setting = config::PreprocessSetting;  ///< depth, covariance, tree

  /// `team` is shared with the caller's other parallel work and must outlive this object.
  FramePreprocessor(const PinholeCamera& camera, const Setting& setting, rt::WorkerTeam& team);

  /// One frame (core/types/rgbd_view.hpp). A GICP source: no tree.
  DepthToPointsStats process(const RgbdView& frame, GaussianCloud& out);
  /// The same, and `tree` rebuilt over out's points (a GICP target). With `grid`, also a copy
  /// of the frame's pixel grid (cleared when the cloud is not organised), for CloudTarget.
  DepthToPointsStats process(const RgbdView& frame, GaussianCloud& out, KdTree& tree,
                             PixelGrid* grid = nullptr);
  /// Owned images (tools, tests): depth in metres; `rgb` empty or of the same size.
  DepthToPointsStats process(const ImageF32& depth_m, const ImageU8& rgb, GaussianCloud& out) {
    return process(view_of(depth_m, rgb), out);
  }
  DepthToPointsStats process(const ImageF32& depth_m, const ImageU8& rgb, GaussianCloud& out,
                             KdTree& tree, PixelGrid* grid = nullptr) {
    return process(view_of(depth_m, rgb), out, tree, grid);
  }

  /// Covariances for points already in `cloud.points_m` (e.g. loaded from a file; no image,
  /// so always through `tree`, which is rebuilt over them).
  void finish(GaussianCloud& cloud, KdTree& tree) const {
    tree.build(cloud.points_m, team_);
    estimate_covariances(tree, setting_.covariance, *team_, cloud);
  }

  /// Points of the last processed frame whose neighbours the image search could not certify
  /// (found with the kd-tree instead); 0 with KnnSearch::kd_tree.
  [[nodiscard]] std::size_t last_knn_fallbacks() const { return last_fallbacks_; }
  /// The most points a frame of this camera can give (every stride-th pixel valid).
  [[nodiscard]] std::size_t max_points() const;
  [[nodiscard]] const PixelGrid& last_grid() const { return grid_; }
  [[nodiscard]] const Setting& setting() const { return setting_; }

 private:
  static RgbdView view_of(const ImageF32& depth_m, const ImageU8& rgb) {
    if (depth_m.empty()) throw std::invalid_argument("depth image is empty");
    return rgbd_view(0, depth_m, rgb);
  }
  /// Covariances of `out`; `tree` is over out's points or null (built here when needed).
  void covariances(GaussianCloud& out, KdTree* tree);

  DepthToPoints depth_;
  Setting setting_;
  rt::WorkerTeam* team_;
  PixelGrid grid_;
  OrganizedKnn organized_;
  KdTree fallback_tree_;
  std::vector<std::vector<std::uint32_t>> pending_;  ///< per team member
  std::vector<std::uint32_t> fallback_points_;
  std::size_t last_fallbacks_ = 0;
};

}  // namespace vigs::tracking
