#include "eval/umeyama.hpp"

#include <Eigen/Geometry>
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
  // std::vector<Vector3d> is contiguous xyz triples, so both sets are viewed as 3xN in place.
  const auto n = static_cast<Eigen::Index>(from.size());
  const Eigen::Map<const Eigen::Matrix3Xd> X(from.front().data(), 3, n);
  const Eigen::Map<const Eigen::Matrix3Xd> Y(to.front().data(), 3, n);
  const bool with_scale = mode == Alignment::kSim3;
  // Eigen::umeyama divides by the source variance for the scale; coincident points would
  // silently give inf/NaN, so they are refused here with the same message as before.
  if (with_scale && (X.colwise() - X.rowwise().mean()).squaredNorm() <= 0.0) {
    throw std::invalid_argument("umeyama: sim3 needs non-coincident points");
  }
  const Eigen::Matrix4d T = Eigen::umeyama(X, Y, with_scale);
  const Eigen::Matrix3d sR = T.topLeftCorner<3, 3>();
  // Eigen returns [s R | t]; the scale is recovered from the (proper) rotation's column norm.
  out.s = with_scale ? sR.col(0).norm() : 1.0;
  out.R = sR / out.s;
  out.t = T.topRightCorner<3, 1>();
  return out;
}

}  // namespace vigs::eval
