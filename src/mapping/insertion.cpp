#include "mapping/insertion.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace vigs::mapping {

void covariance_to_rotation_scale(const Eigen::Matrix3d& cov, Eigen::Quaterniond& q,
                                  Eigen::Vector3d& std_dev) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(0.5 * (cov + cov.transpose()));
  // ascending eigenvalues -> largest first
  Eigen::Matrix3d V;
  for (int k = 0; k < 3; ++k) {
    V.col(k) = es.eigenvectors().col(2 - k);
    std_dev(k) = std::sqrt(std::max(0.0, es.eigenvalues()(2 - k)));
  }
  if (V.determinant() < 0) V.col(2) = -V.col(2);
  q = Eigen::Quaterniond(V);
  q.normalize();
}

void GaussianInserter::rebuild(const GaussianMap& map) {
  const std::size_t bricks = occupied_.bricks();  // about as many as before the prune
  occupied_.clear();
  occupied_.reserve(bricks);
  const float* m = map.mean_w.data();
  for (std::size_t i = 0; i < map.size(); ++i)
    occupied_.insert(m[3 * i], m[3 * i + 1], m[3 * i + 2]);
}

void GaussianInserter::forget(const GaussianMap& map, const std::vector<char>& keep) {
  const std::size_t n = std::min(map.size(), keep.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (!keep[i]) occupied_.erase(map.mean_w[3 * i], map.mean_w[3 * i + 1], map.mean_w[3 * i + 2]);
  }
}

void footprint_scale_opacity(const InsertSettings& s, double z_m, double sample_angle_rad,
                             const Eigen::Vector3d& cov_sd, Eigen::Vector3d& sd, double& opacity) {
  const double d = std::max(z_m * sample_angle_rad, s.voxel_m);
  const double stretch = cov_sd(1) > 0 ? std::clamp(cov_sd(0) / cov_sd(1), 1.0, 3.0) : 1.0;
  sd(0) = s.cover * d * stretch;
  sd(1) = s.cover * d;
  sd(2) = std::min(cov_sd(2), s.thin * d);
  const double t = cov_sd(2) / d;
  opacity = std::clamp(s.opacity * std::exp(-0.5 * t * t), 0.05, s.opacity);
}

std::size_t GaussianInserter::insert(GaussianMap& map, const KeyframeGaussians& kf,
                                     const std::vector<char>* keep) {
  const std::size_t n = kf.points_c.size();
  const Eigen::Matrix3d R_w_c = kf.T_w_c.linear();
  const bool footprint = kf.sample_angle_rad > 0.0;
  const float flat_logit = static_cast<float>(std::log(s_.opacity / (1.0 - s_.opacity)));
  std::size_t added = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (keep && !(*keep)[i]) continue;
    const Eigen::Vector3d p_c = kf.points_c[i].cast<double>();
    if (!(p_c.z() > 0) || !p_c.allFinite()) continue;
    const Eigen::Vector3d p_w = kf.T_w_c * p_c;
    if (!occupied_.insert(p_w.x(), p_w.y(), p_w.z())) continue;
    Eigen::Quaterniond q_c;
    Eigen::Vector3d cov_sd, sd;
    covariance_to_rotation_scale(kf.covariances_c[i].cast<double>(), q_c, cov_sd);
    float logit_op = flat_logit;
    if (footprint) {
      double op = s_.opacity;
      footprint_scale_opacity(s_, p_c.z(), kf.sample_angle_rad, cov_sd, sd, op);
      logit_op = static_cast<float>(std::log(op / (1.0 - op)));
    } else {
      sd = cov_sd / std::max(1.0, 2.0 * std::pow(p_c.z(), 1.5));
    }
    const Eigen::Quaterniond q_w(R_w_c * q_c.toRotationMatrix());
    const float mean[3] = {static_cast<float>(p_w.x()), static_cast<float>(p_w.y()),
                           static_cast<float>(p_w.z())};
    float log_s[3];
    for (int k = 0; k < 3; ++k)
      log_s[k] = static_cast<float>(std::log(std::max(s_.min_scale_m, sd(k))));
    const float quat[4] = {static_cast<float>(q_w.w()), static_cast<float>(q_w.x()),
                           static_cast<float>(q_w.y()), static_cast<float>(q_w.z())};
    const float rgb[3] = {kf.colors[i].x(), kf.colors[i].y(), kf.colors[i].z()};
    map.push_back(mean, log_s, quat, logit_op, rgb);
    ++added;
  }
  return added;
}

}  // namespace vigs::mapping
