#include "eval/umeyama.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <stdexcept>

namespace vigs::eval {

Alignment parse_alignment(const std::string& name) {
  if (name == "none") return Alignment::kNone;
  if (name == "se3") return Alignment::kSe3;
  if (name == "sim3") return Alignment::kSim3;
  throw std::invalid_argument("unknown alignment '" + name + "' (none | se3 | sim3)");
}

const char* alignment_name(Alignment a) {
  switch (a) {
    case Alignment::kNone:
      return "none";
    case Alignment::kSe3:
      return "se3";
    case Alignment::kSim3:
      return "sim3";
  }
  return "?";
}

Sim3 umeyama_align(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to,
                   Alignment mode) {
  if (from.size() != to.size()) {
    throw std::invalid_argument("umeyama: point sets differ in size");
  }
  Sim3 out;
  if (mode == Alignment::kNone) return out;
  if (from.size() < 3) throw std::invalid_argument("umeyama: need at least 3 point pairs");
  const double n = static_cast<double>(from.size());
  Eigen::Vector3d mean_x = Eigen::Vector3d::Zero(), mean_y = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < from.size(); ++i) {
    mean_x += from[i];
    mean_y += to[i];
  }
  mean_x /= n;
  mean_y /= n;
  double sigma_x = 0.0;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < from.size(); ++i) {
    const Eigen::Vector3d dx = from[i] - mean_x;
    sigma_x += dx.squaredNorm();
    cov += (to[i] - mean_y) * dx.transpose();
  }
  sigma_x /= n;
  cov /= n;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) S(2, 2) = -1.0;
  out.R = svd.matrixU() * S * svd.matrixV().transpose();
  if (mode == Alignment::kSim3) {
    if (sigma_x <= 0.0) throw std::invalid_argument("umeyama: sim3 needs non-coincident points");
    out.s = (svd.singularValues().asDiagonal() * S).trace() / sigma_x;
  }
  out.t = mean_y - out.s * (out.R * mean_x);
  return out;
}

}  // namespace vigs::eval
