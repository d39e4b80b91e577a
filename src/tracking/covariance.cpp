#include "tracking/covariance.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace vigs::tracking {

Eigen::Matrix3f regularize_covariance(const Eigen::Matrix3f& raw_m2,
                                      const CovarianceSetting& setting) {
  if (setting.regularization == Regularization::none) {
    return raw_m2;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(raw_m2.cast<double>());
  // Eigen orders eigenvalues ascending: l3 <= l2 <= l1.
  const Eigen::Vector3d l = eig.eigenvalues();
  const Eigen::Matrix3d& U = eig.eigenvectors();
  Eigen::Vector3d values;
  if (setting.regularization == Regularization::plane) {
    values = Eigen::Vector3d(setting.epsilon, 1.0, 1.0);
  } else if (!(l(1) > 0.0)) {
    return Eigen::Matrix3f::Identity();
  } else {
    values = (l / l(1)).cwiseMax(setting.epsilon);
  }
  return (U * values.asDiagonal() * U.transpose()).cast<float>();
}

void estimate_covariances(const KdTree& tree, const CovarianceSetting& setting, ForkJoin& team,
                          GaussianCloud& cloud) {
  const std::size_t n = cloud.points_m.size();
  cloud.cov_raw_m2.resize(n);
  cloud.cov_m2.resize(n);
  const int k = std::clamp(setting.k_neighbors, 1, KdTree::kMaxK);
  team.run([&](int t) {
    std::uint32_t idx[KdTree::kMaxK];
    float d2[KdTree::kMaxK];
    const std::vector<std::uint32_t>& order = tree.leaf_order();
    ForkJoin::for_each_interleaved(n, t, team.size(), 256, [&](std::size_t o) {
      const std::uint32_t i = order[o];
      const int found = tree.knn(cloud.points_m[i], k, idx, d2);
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      Eigen::Matrix3d sum_sq = Eigen::Matrix3d::Zero();
      for (int j = 0; j < found; ++j) {
        const Eigen::Vector3d p = cloud.points_m[idx[j]].cast<double>();
        sum += p;
        sum_sq.noalias() += p * p.transpose();
      }
      Eigen::Matrix3f raw = Eigen::Matrix3f::Zero();
      if (found > 0) {
        const Eigen::Vector3d mean = sum / found;
        raw = (sum_sq / found - mean * mean.transpose()).cast<float>();
      }
      cloud.cov_raw_m2[i] = raw;
      cloud.cov_m2[i] = regularize_covariance(raw, setting);
    });
  });
}

}  // namespace vigs::tracking
