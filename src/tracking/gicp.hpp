#pragma once
// Generalized ICP (Segal et al. 2009) over SE(3): minimises
//   sum_i rho( d_i^T (C_t,i + R C_s,i R^T)^-1 d_i ),  d_i = q_i - T p_i,
// with nearest-neighbour correspondences bounded by a maximum distance, a robust kernel,
// and Levenberg–Marquardt steps (gicp_factor.hpp gives the parameterisation).
//
// Direction: align(target, source, T_t_s_init) returns T_t_s, the pose that maps SOURCE
// points into the TARGET frame (p_t = T_t_s * p_s). For two camera frames with poses
// T_w_0 (source) and T_w_2 (target) that is T_w_2^-1 * T_w_0.
//
// Determinism: each linearisation deals the source points to the threads in fixed blocks of
// 256 (round robin), each thread sums its blocks in order, and the per-thread partial H, b
// are summed in thread order, so the result is bit-identical run to run for the same
// num_threads.
#include <optional>
#include <string_view>
#include <vector>

#include "core/geometry/se3.hpp"
#include "rt/worker_team.hpp"
#include "tracking/gaussian_cloud.hpp"
#include "tracking/gicp_factor.hpp"
#include "tracking/kdtree.hpp"
#include "tracking/organized_knn.hpp"
#include "tracking/pixel_grid.hpp"
#include "tracking/pose_prior.hpp"

namespace vigs::tracking {

enum class GicpVerdict {
  converged,      ///< increments fell below both thresholds
  not_converged,  ///< max_iterations reached first
  diverged,       ///< too few correspondences, or non-finite numbers
  degenerate,     ///< the Hessian leaves a direction unconstrained (see degenerate_eigen_ratio)
};
std::string_view to_string(GicpVerdict verdict);

struct GicpResult {
  geometry::Pose T_t_s = geometry::Pose::Identity();  ///< source -> target
  /// Gauss–Newton Hessian sum w J^T M J of the last linearisation (at T_t_s, or one
  /// converged step before it): the information matrix of the left increment
  /// xi = [rotation (rad); translation (m)] in the target frame. With the dimensionless
  /// regularised covariances it is a relative information; scale it before publishing it as
  /// a covariance. num_inliers, inlier_ratio, overlap_ratio and cost are from the same
  /// linearisation.
  Matrix6d information = Matrix6d::Zero();
  /// information + the prior's J^T Lambda J at T_t_s when align() was given a PosePrior (the
  /// posterior information of the fused estimate, same units as the prior); else information.
  Matrix6d information_posterior = Matrix6d::Zero();
  bool prior_used = false;
  double prior_cost = 0.0;  ///< e^T Lambda e of the prior at T_t_s (0 without a prior)
  /// Degeneracy: eigen-decomposition of the scaled GICP-only Hessian (see eigen_ratio).
  /// Directions whose eigenvalue is below degenerate_eigen_ratio times the largest, counted,
  /// and the weakest one as a unit 6-vector [rotation about the matched centroid (scaled by
  /// the RMS spread); translation] in the target frame.
  int degenerate_directions = 0;
  Vector6d weakest_direction = Vector6d::Zero();
  double inlier_ratio = 0.0;   ///< source points with a correspondence / source points
  double overlap_ratio = 0.0;  ///< source points with a target point within overlap distance
  int num_inliers = 0;
  int iterations = 0;        ///< accepted + rejected LM steps
  double cost = 0.0;         ///< robust cost at T_t_s
  double eigen_ratio = 0.0;  ///< min/max eigenvalue of the scaled Hessian (degeneracy test)
  GicpVerdict verdict = GicpVerdict::diverged;
};

class Gicp {
 public:
  using Setting = config::GicpSetting;  ///< defaults: config/tracking_components.hpp

  Gicp();
  /// `team`: the worker team to run on (the Tracker shares its own; it must outlive this Gicp
  /// and have setting.num_threads members). Null: the Gicp owns a team of setting.num_threads
  /// normal-priority workers named `tracker_w<m>`.
  explicit Gicp(const Setting& setting, rt::WorkerTeam* team = nullptr);

  /// Target: anything with nearest(q, max_sq_dist, index, sq_dist), point(i) and cov(i)
  /// (CloudTarget below, LocalMap). Source covariances are source.cov_m2.
  /// With `prior` (nullable) its factor is added to the least squares (pose_prior.hpp): the
  /// prior's information must be in the GICP cost's units (the caller scales it).
  template <class Target>
  GicpResult align(const Target& target, const GaussianCloud& source,
                   const geometry::Pose& T_t_s_init, const PosePrior* prior = nullptr);
  /// Sizes the per-point buffers for sources of up to `max_points` points (align() of no more
  /// then does not allocate).
  void reserve(std::size_t max_points) { hints_.reserve(max_points); }

  [[nodiscard]] const Setting& setting() const { return setting_; }

 private:
  struct Partial {
    GicpSystem system;
    double sum_sq_range;
    Eigen::Vector3d sum_y;
    int inliers;
    int overlapping;
  };
  struct Linearization {
    Matrix6d H = Matrix6d::Zero();  ///< total (with the prior's terms when there is one)
    Vector6d b = Vector6d::Zero();
    double cost = 0.0;
    Matrix6d H_data = Matrix6d::Zero();  ///< GICP terms only
    double cost_data = 0.0;
    double cost_prior = 0.0;
    double sum_sq_range = 0.0;
    Eigen::Vector3d sum_y = Eigen::Vector3d::Zero();
    int inliers = 0;
    int overlapping = 0;
  };
  template <class Target>
  Linearization linearize(const Target& target, const GaussianCloud& source,
                          const geometry::Pose& T_t_s);

  Setting setting_;
  std::optional<rt::WorkerTeam> own_team_;
  rt::WorkerTeam* team_;
  std::vector<Partial> partials_;
  /// Per source point, its target match at the previous linearisation of this align() call
  /// (KdTree::kNoHint when none): seeds the next nearest-neighbour search of targets that
  /// take a hint. Grows with the largest source seen, then is reused.
  std::vector<std::uint32_t> hints_;
};

/// GICP target made of one frame's cloud and a kd-tree over its points, and optionally the
/// frame's pixel grid (FramePreprocessor::process with a grid): correspondences are then found
/// through the image (OrganizedKnn::nearest, exact), the tree serving queries the image
/// search cannot certify.
struct CloudTarget {
  const GaussianCloud* cloud = nullptr;
  const KdTree* tree = nullptr;
  const PixelGrid* grid = nullptr;

  bool nearest(const Eigen::Vector3f& q, float max_sq_dist, std::uint32_t& index, float& sq_dist,
               std::uint32_t hint = KdTree::kNoHint) const {
    if (grid != nullptr && grid->describes(cloud->size())) {
      const int r = OrganizedKnn::shared().nearest(*grid, cloud->points_m, q, max_sq_dist, hint,
                                                   index, sq_dist);
      if (r >= 0) {
        return r == 1;
      }
    }
    return tree->nearest(q, max_sq_dist, index, sq_dist, hint);
  }
  [[nodiscard]] const Eigen::Vector3f& point(std::uint32_t i) const { return cloud->points_m[i]; }
  [[nodiscard]] const Eigen::Matrix3f& cov(std::uint32_t i) const { return cloud->cov_m2[i]; }
};

}  // namespace vigs::tracking
