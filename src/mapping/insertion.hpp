#pragma once
// Insertion of keyframe points as new Gaussians. Each covariance is eigen-decomposed: the
// eigenvectors (made a proper rotation, det +1) give the orientation and the square roots of
// the eigenvalues the standard deviations, divided by max(1, 2 z^1.5) with z the point's depth
// in metres, exactly as GS-ICP SLAM scales its GICP covariances before mapping. Initial opacity
// is 0.1. A voxel-occupancy set skips points whose voxel already holds a Gaussian, so that
// revisits do not grow the map without bound.
#include <cstdint>
#include <unordered_set>

#include "core/config/mapping_components.hpp"
#include "mapping/gaussian_map.hpp"
#include "mapping/keyframe_gaussians.hpp"

namespace vigs::mapping {

using config::InsertSettings;  // defaults: core/config/mapping_components.hpp

class GaussianInserter {
 public:
  explicit GaussianInserter(InsertSettings s = {}) : s_(s) {}

  /// Appends the keyframe's new Gaussians to `map`; returns how many were added.
  std::size_t insert(GaussianMap& map, const KeyframeGaussians& kf);

  /// Rebuilds the occupancy from the map (after pruning or loading).
  void rebuild(const GaussianMap& map);

  [[nodiscard]] std::size_t occupied_voxels() const { return occupied_.size(); }

 private:
  [[nodiscard]] std::uint64_t key(const Eigen::Vector3d& p_w) const;

  InsertSettings s_;
  std::unordered_set<std::uint64_t> occupied_;
};

/// Orientation (w x y z) and standard deviations of a covariance, largest axis first; the
/// rotation is proper (det +1).
void covariance_to_rotation_scale(const Eigen::Matrix3d& cov, Eigen::Quaterniond& q,
                                  Eigen::Vector3d& std_dev);

}  // namespace vigs::mapping
