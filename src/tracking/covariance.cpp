#include "tracking/covariance.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace vigs::tracking {

namespace {
constexpr double kZeroEigenvalueRatio = 1e-7;
}  // namespace

Eigen::Matrix3f regularize_covariance(const Eigen::Matrix3f& raw_m2,
                                      const CovarianceSetting& setting) {
  if (setting.regularization == Regularization::none) {
    return raw_m2;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(raw_m2.cast<double>());
  // Eigen orders eigenvalues ascending: l3 <= l2 <= l1 (header naming) are l(0..2).
  const Eigen::Vector3d l = eig.eigenvalues();
  const Eigen::Matrix3d& U = eig.eigenvectors();
  Eigen::Vector3d values;
  if (setting.regularization == Regularization::plane) {
    values = Eigen::Vector3d(setting.epsilon, 1.0, 1.0);
  } else if (!(l(1) > kZeroEigenvalueRatio * l(2))) {
    // A middle eigenvalue below the float resolution of the largest is zero (collinear or
    // coincident neighbours): no ellipse shape to normalise by.
    return Eigen::Matrix3f::Identity();
  } else {
    values = (l / l(1)).cwiseMax(setting.epsilon);
  }
  return (U * values.asDiagonal() * U.transpose()).cast<float>();
}

namespace {

// Raw and regularised covariance of point i from its `found` neighbours.
void covariance_from_neighbours(const CovarianceSetting& setting, std::uint32_t i,
                                const std::uint32_t* idx, int found, GaussianCloud& cloud) {
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
}

int clamped_k(const CovarianceSetting& setting) {
  return std::clamp(setting.k_neighbors, 1, KdTree::kMaxK);
}

}  // namespace

void estimate_covariances(const KdTree& tree, const CovarianceSetting& setting,
                          rt::WorkerTeam& team, GaussianCloud& cloud) {
  const std::size_t n = cloud.points_m.size();
  cloud.cov_raw_m2.resize(n);
  cloud.cov_m2.resize(n);
  const int k = clamped_k(setting);
  team.run([&](int t) {
    std::uint32_t idx[KdTree::kMaxK];
    float d2[KdTree::kMaxK];
    const std::vector<std::uint32_t>& order = tree.leaf_order();
    rt::WorkerTeam::for_each_interleaved(n, t, team.size(), 256, [&](std::size_t o) {
      const std::uint32_t i = order[o];
      const int found = tree.knn(cloud.points_m[i], k, idx, d2);
      covariance_from_neighbours(setting, i, idx, found, cloud);
    });
  });
}

void estimate_covariances(const PixelGrid& grid, const OrganizedKnn& knn,
                          const CovarianceSetting& setting, rt::WorkerTeam& team,
                          GaussianCloud& cloud, std::vector<std::vector<std::uint32_t>>& pending) {
  const std::size_t n = cloud.points_m.size();
  cloud.cov_raw_m2.resize(n);
  cloud.cov_m2.resize(n);
  pending.resize(static_cast<std::size_t>(team.size()));
  const int k = clamped_k(setting);
  team.run([&](int t) {
    std::uint32_t idx[KdTree::kMaxK];
    float d2[KdTree::kMaxK];
    std::vector<std::uint32_t>& left = pending[static_cast<std::size_t>(t)];
    left.clear();
    // Points are in raster order, so consecutive queries share their image neighbourhoods.
    rt::WorkerTeam::for_each_interleaved(n, t, team.size(), 256, [&](std::size_t o) {
      const auto i = static_cast<std::uint32_t>(o);
      const int found = knn.knn(grid, cloud.points_m, i, k, idx, d2);
      if (found < 0) {
        left.push_back(i);
        return;
      }
      covariance_from_neighbours(setting, i, idx, found, cloud);
    });
  });
}

void estimate_covariances_of(const KdTree& tree, const CovarianceSetting& setting,
                             const std::vector<std::uint32_t>& points, GaussianCloud& cloud) {
  const int k = clamped_k(setting);
  std::uint32_t idx[KdTree::kMaxK];
  float d2[KdTree::kMaxK];
  for (const std::uint32_t i : points) {
    const int found = tree.knn(cloud.points_m[i], k, idx, d2);
    covariance_from_neighbours(setting, i, idx, found, cloud);
  }
}

}  // namespace vigs::tracking
