#pragma once
// Template bodies of Gicp::align / Gicp::linearize. Included only by the .cpp files that
// instantiate them for a target type (gicp.cpp: CloudTarget; local_map.cpp: LocalMap).
#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "tracking/gicp.hpp"

namespace vigs::tracking {

inline constexpr std::size_t kBlock = 256;  ///< source points per work block
/// A refused step smaller than this many convergence eps ends the search (converged).
inline constexpr double kRefusedStepEps = 1.5;

template <class Target>
Gicp::Linearization Gicp::linearize(const Target& target, const GaussianCloud& source,
                                    const geometry::Pose& T_t_s) {
  const Eigen::Matrix3d R = T_t_s.linear();
  const Eigen::Vector3d t = T_t_s.translation();
  const float max_sq = static_cast<float>(setting_.max_correspondence_distance_m *
                                          setting_.max_correspondence_distance_m);
  const float overlap_sq =
      static_cast<float>(setting_.overlap_distance_m * setting_.overlap_distance_m);
  const std::size_t n = source.size();
  team_->run([&](int th) {
    Partial& part = partials_[static_cast<std::size_t>(th)];
    part.system = GicpSystem{};
    part.sum_sq_range = 0.0;
    part.sum_y.setZero();
    part.inliers = 0;
    part.overlapping = 0;
    rt::WorkerTeam::for_each_interleaved(n, th, team_->size(), kBlock, [&](std::size_t i) {
      const Eigen::Vector3d y = R * source.points_m[i].cast<double>() + t;
      std::uint32_t j = 0;
      float d2 = 0.0f;
      bool matched = false;
      if constexpr (requires { target.nearest(y.cast<float>(), max_sq, j, d2, hints_[i]); }) {
        // Hint: this point's match at the last linearisation (none at the first).
        matched = target.nearest(y.cast<float>(), max_sq, j, d2, hints_[i]);
        hints_[i] = matched ? j : KdTree::kNoHint;
      } else {
        matched = target.nearest(y.cast<float>(), max_sq, j, d2);
      }
      if (!matched) {
        return;
      }
      Eigen::Matrix3d M;
      if (!gicp_information(target.cov(j).template cast<double>(), R,
                            source.cov_m2[i].cast<double>(), M)) {
        return;
      }
      const Eigen::Vector3d r = target.point(j).template cast<double>() - y;
      part.system.add(y, r, M, setting_.kernel, setting_.kernel_width);
      part.sum_y += y;
      part.sum_sq_range += y.squaredNorm();
      ++part.inliers;
      if (d2 <= overlap_sq) {
        ++part.overlapping;
      }
    });
  });
  Linearization lin;
  for (const Partial& part : partials_) {  // fixed order: bit-identical sums
    part.system.add_to(lin.H, lin.b);
    lin.cost += part.system.cost;
    lin.sum_sq_range += part.sum_sq_range;
    lin.sum_y += part.sum_y;
    lin.inliers += part.inliers;
    lin.overlapping += part.overlapping;
  }
  return lin;
}

template <class Target>
GicpResult Gicp::align(const Target& target, const GaussianCloud& source,
                       const geometry::Pose& T_t_s_init, const PosePrior* prior) {
  GicpResult result;
  result.T_t_s = T_t_s_init;
  if (!T_t_s_init.matrix().allFinite()) {
    return result;  // verdict stays diverged: nothing to start from
  }
  geometry::Pose T = T_t_s_init;
  hints_.assign(source.size(), KdTree::kNoHint);  // allocates only when the source grows
  // Total system: GICP terms plus the prior's at the same pose.
  const auto with_prior = [&](Linearization& l, const geometry::Pose& at) {
    l.H_data = l.H;
    l.cost_data = l.cost;
    if (prior != nullptr) {
      l.cost_prior = add_pose_prior(*prior, at, l.H, l.b);
      l.cost += l.cost_prior;
    }
  };
  Linearization lin = linearize(target, source, T);
  with_prior(lin, T);
  double lambda = setting_.lm_lambda_init;
  bool converged = false;
  int iterations = 0;
  while (iterations < setting_.max_iterations && lin.inliers >= setting_.min_inliers) {
    ++iterations;
    // Marquardt damping, relative to H's own diagonal: lambda means the same whatever the
    // number of points and the units of each coordinate.
    Matrix6d A = lin.H;
    A.diagonal() += lambda * lin.H.diagonal().cwiseMax(1e-12);
    const Vector6d dx = A.ldlt().solve(-lin.b);
    if (!dx.allFinite()) {
      break;
    }
    geometry::Pose T_new = geometry::se3_exp_rot_trans(dx) * T;
    T_new.linear() = geometry::normalize_rotation<double>(T_new.linear());
    if (dx.head<3>().norm() < setting_.rotation_eps_rad() &&
        dx.tail<3>().norm() < setting_.translation_eps_m) {
      // Converged: take the small final step without another correspondence search. H,
      // inliers and cost are those of the last linearisation, at most eps away.
      T = T_new;
      converged = true;
      break;
    }
    Linearization lin_new = linearize(target, source, T_new);
    with_prior(lin_new, T_new);
    // Accept when the cost does not rise; fewer inliers can only lower the cost, so a step
    // that loses most of them is refused as well.
    if (lin_new.inliers >= setting_.min_inliers && lin_new.cost <= lin.cost &&
        2 * lin_new.inliers >= lin.inliers) {
      T = T_new;
      lin = lin_new;
      lambda = std::max(lambda * 0.1, 1e-12);
    } else {
      // The cost rose. Near the optimum that is the correspondences switching, not the
      // quadratic model failing: a refused step within a few eps of converged ends the search
      // at the current pose instead of damping it down step by refused step.
      if (dx.head<3>().norm() < kRefusedStepEps * setting_.rotation_eps_rad() &&
          dx.tail<3>().norm() < kRefusedStepEps * setting_.translation_eps_m) {
        converged = true;
        break;
      }
      lambda = std::max(lambda * 10.0, 1e-3);
      if (lambda > 1e3) {
        // No descent direction left: the current pose is a (local) minimum.
        converged = dx.head<3>().norm() < 10.0 * setting_.rotation_eps_rad() &&
                    dx.tail<3>().norm() < 10.0 * setting_.translation_eps_m;
        break;
      }
    }
  }
  result.T_t_s = T;
  result.information = lin.H_data;
  result.information_posterior = lin.H;
  result.prior_used = prior != nullptr;
  result.prior_cost = lin.cost_prior;
  result.iterations = iterations;
  result.cost = lin.cost;
  result.num_inliers = lin.inliers;
  const double n = static_cast<double>(std::max<std::size_t>(source.size(), 1));
  result.inlier_ratio = lin.inliers / n;
  result.overlap_ratio = lin.overlapping / n;

  if (lin.inliers < setting_.min_inliers || !lin.H.allFinite() || !T.matrix().allFinite()) {
    result.verdict = GicpVerdict::diverged;
    return result;
  }
  // Degeneracy: re-express H for rotations about the centroid c of the matched points
  // (xi = G xi_c, G = [I 0; [c]x I]), scale rotations by the RMS spread L about c, and
  // compare the extreme eigenvalues.
  const Eigen::Vector3d c = lin.sum_y / lin.inliers;
  const double L2 = std::max(lin.sum_sq_range / lin.inliers - c.squaredNorm(), 1e-6);
  Matrix6d G = Matrix6d::Identity();
  G.bottomLeftCorner<3, 3>() = geometry::hat<double>(c);
  Vector6d s;
  s << Eigen::Vector3d::Constant(1.0 / std::sqrt(L2)), Eigen::Vector3d::Ones();
  const Matrix6d Hs = s.asDiagonal() * (G.transpose() * lin.H_data * G) * s.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eig(Hs);
  const Vector6d ev = eig.eigenvalues();
  result.eigen_ratio = ev(5) > 0.0 ? std::max(ev(0), 0.0) / ev(5) : 0.0;
  for (int k = 0; k < 6; ++k) {
    if (!(ev(k) >= setting_.degenerate_eigen_ratio * ev(5))) ++result.degenerate_directions;
  }
  result.weakest_direction = eig.eigenvectors().col(0);
  if (result.eigen_ratio < setting_.degenerate_eigen_ratio) {
    result.verdict = GicpVerdict::degenerate;
  } else {
    result.verdict = converged ? GicpVerdict::converged : GicpVerdict::not_converged;
  }
  return result;
}

}  // namespace vigs::tracking
