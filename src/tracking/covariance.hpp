#pragma once
// Per-point covariances from the k nearest neighbours, and their regularisation.
//
// Raw covariance: sample covariance of the point's k nearest neighbours (the point itself
// included), divided by the neighbour count; metres squared. It is stored unchanged in
// GaussianCloud::cov_raw_m2 for the mapper.
//
// Regularised covariance (GaussianCloud::cov_m2, used by GICP), from the eigen-decomposition
// C = U diag(l1 >= l2 >= l3) U^T of the raw covariance:
//  - normalized_ellipse: GS-ICP SLAM's NORMALIZED_ELLIPSE (its fast_gicp fork, branch
//    gs_icp_slam, FastGICP::calculate_covariances): eigenvalues divided by the MIDDLE one,
//    (l1/l2, 1, l3/l2), each clamped below at epsilon (1e-3). The ellipse keeps its shape
//    but is scale-free (dimensionless). GS-ICP sets 1e-9*I when l2 == 0 (collinear or
//    coincident neighbours); we use the identity there instead (and for l2 < 1e-7 l1, below the
//    float resolution of the covariance), because a near-zero
//    covariance would outweigh every other correspondence. GS-ICP also drops neighbours
//    whose squared distance exceeds knn_max_distance (its script default 99999 m^2, i.e.
//    off) and divides by k rather than by the neighbours kept; with the filter off both
//    agree with this implementation.
//  - plane: U diag(1, 1, epsilon) U^T (fast_gicp's PLANE): every point a flat disc.
//  - none: the raw covariance (m^2), unchanged.
#include <cstdint>
#include <vector>

#include "core/config/tracking_components.hpp"
#include "rt/worker_team.hpp"
#include "tracking/gaussian_cloud.hpp"
#include "tracking/kdtree.hpp"
#include "tracking/organized_knn.hpp"
#include "tracking/pixel_grid.hpp"

namespace vigs::tracking {

// Declared with the other tracking settings (config/tracking_components.hpp), where the
// defaults are; the robot file documents them (config/tracking_settings.hpp).
using config::CovarianceSetting;
using config::KnnSearch;
using config::Regularization;

/// Regularised covariance of one raw covariance (see the header comment).
Eigen::Matrix3f regularize_covariance(const Eigen::Matrix3f& raw_m2,
                                      const CovarianceSetting& setting);

/// Fills cloud.cov_raw_m2 and cloud.cov_m2 for every point; `tree` must index
/// cloud.points_m. Points go to the team in fixed blocks (rt::WorkerTeam::for_each_interleaved).
void estimate_covariances(const KdTree& tree, const CovarianceSetting& setting,
                          rt::WorkerTeam& team, GaussianCloud& cloud);

/// The same for an organised cloud (`grid` describes it), neighbours from `knn` through the
/// image. Points the image search cannot certify are not filled: team member t appends them to
/// pending[t] (cleared first; one vector per member, reserved by the caller to stay
/// allocation-free) for estimate_covariances_of().
void estimate_covariances(const PixelGrid& grid, const OrganizedKnn& knn,
                          const CovarianceSetting& setting, rt::WorkerTeam& team,
                          GaussianCloud& cloud, std::vector<std::vector<std::uint32_t>>& pending);

/// Covariances of the listed points only (cov vectors already sized), neighbours from `tree`.
void estimate_covariances_of(const KdTree& tree, const CovarianceSetting& setting,
                             const std::vector<std::uint32_t>& points, GaussianCloud& cloud);

}  // namespace vigs::tracking
