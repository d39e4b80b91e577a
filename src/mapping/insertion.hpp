#pragma once
// Insertion of keyframe points as new Gaussians, made to render the keyframe's own view before
// any optimisation step ("view-gated" insertion):
// - orientation from the point's covariance (kNN or image-grid): eigenvectors, made a proper
//   rotation (det +1), largest axis first, so the third axis is the surface normal;
// - scale covering the sample's footprint: a sample at depth z taken every sample_angle_rad
//   stands for a patch d = max(z * sample_angle_rad, voxel) wide; the two in-plane standard
//   deviations are cover * d, the first one stretched by the covariance's own in-plane
//   anisotropy (a slanted surface's samples lie farther apart along the slant, at most 3x), the
//   normal one the covariance's thickness, at most thin * d;
// - opacity from depth confidence: opacity * exp(-0.5 (t / d)^2) with t the covariance's
//   thickness (depth noise and non-planarity; an edge's straddling neighbours give a thick,
//   uncertain patch), at least 0.05;
// - colour from the pixel.
// Without a sample angle (0) the GS-ICP SLAM rule is kept: standard deviations divided by
// max(1, 2 z^1.5) and the flat opacity. A voxel-occupancy set skips points whose voxel already
// holds a Gaussian (voxel_occupancy.hpp), so that revisits do not grow the map without bound.
#include <cstdint>
#include <vector>

#include "core/config/mapping_components.hpp"
#include "mapping/gaussian_map.hpp"
#include "mapping/keyframe_gaussians.hpp"
#include "mapping/voxel_occupancy.hpp"

namespace vigs::mapping {

using config::InsertSettings;  // defaults: core/config/mapping_components.hpp

class GaussianInserter {
 public:
  explicit GaussianInserter(InsertSettings s = {}) : s_(s), occupied_(s.voxel_m) {}

  /// Appends the keyframe's new Gaussians to `map`; returns how many were added. With `keep`
  /// (one per point), points whose entry is 0 are skipped.
  std::size_t insert(GaussianMap& map, const KeyframeGaussians& kf,
                     const std::vector<char>* keep = nullptr);

  /// Rebuilds the occupancy from the map (after pruning or loading): O(map size).
  void rebuild(const GaussianMap& map);
  /// Frees the voxels of the Gaussians about to be removed (keep[i] == 0), at their current
  /// positions: O(removed), where a rebuild is O(map) -- on a live 60 s run, rebuilding after
  /// every keyframe's see-through pruning took half the mapper's time. A voxel that another
  /// Gaussian has also moved into reads free until the next rebuild (after the next prune), so
  /// one more Gaussian may be added there.
  void forget(const GaussianMap& map, const std::vector<char>& keep);

  [[nodiscard]] std::size_t occupied_voxels() const { return occupied_.voxels(); }
  /// Bytes held by the occupancy (voxel_occupancy.hpp).
  [[nodiscard]] std::size_t occupancy_bytes() const { return occupied_.bytes(); }
  [[nodiscard]] const InsertSettings& settings() const { return s_; }

 private:
  InsertSettings s_;
  VoxelOccupancy occupied_;  ///< voxels that hold a Gaussian
};

/// Orientation (w x y z) and standard deviations of a covariance, largest axis first; the
/// rotation is proper (det +1).
void covariance_to_rotation_scale(const Eigen::Matrix3d& cov, Eigen::Quaterniond& q,
                                  Eigen::Vector3d& std_dev);

/// The initial standard deviations (largest first, metres) and opacity of a sample at depth
/// z_m whose covariance has standard deviations `cov_sd` (largest first), under the rules above.
void footprint_scale_opacity(const InsertSettings& s, double z_m, double sample_angle_rad,
                             const Eigen::Vector3d& cov_sd, Eigen::Vector3d& sd, double& opacity);

}  // namespace vigs::mapping
