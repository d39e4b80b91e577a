#pragma once
// Umeyama (1991) least-squares similarity between point sets: finds s, R, t minimising
// sum_i |y_i - (s R x_i + t)|^2. se3 fixes s = 1, none returns the identity.
// The solve is Eigen::umeyama (Eigen/Geometry); this header adds the evo-style mode names,
// the input checks and the s/R/t split the ATE/RPE code uses.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace vigs::eval {

enum class Alignment { kNone, kSe3, kSim3 };

/// Parses "none" | "se3" | "sim3"; throws std::invalid_argument otherwise.
Alignment parse_alignment(const std::string& name);
const char* alignment_name(Alignment a);

struct Sim3 {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double s = 1.0;

  [[nodiscard]] Eigen::Vector3d apply(const Eigen::Vector3d& x) const { return s * (R * x) + t; }
};

/// Aligns `from` onto `to` (same length, >= 3 points for se3/sim3 unless degenerate).
/// Throws std::invalid_argument on mismatched or too short input.
Sim3 umeyama_align(const std::vector<Eigen::Vector3d>& from, const std::vector<Eigen::Vector3d>& to,
                   Alignment mode);

}  // namespace vigs::eval
