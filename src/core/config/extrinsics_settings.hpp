#pragma once
#include <array>
#include <cmath>

#include "core/config/visitor.hpp"

namespace vigs::config {

/// Camera-to-body (IMU) transform T_b_c: p_b = R_b_c * p_c + t_b_c.
/// Default: uHumans2 (camera z forward = body x, camera x right = body -y).
struct ExtrinsicsSettings {
  std::array<double, 9> R_b_c = {0, 0, 1, -1, 0, 0, 0, -1, 0};  ///< row-major
  std::array<double, 3> t_b_c_m = {0.0, 0.05, 0.0};

  [[nodiscard]] bool rotation_is_proper(double tol = 1e-6) const {
    const auto& r = R_b_c;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        double dot = 0.0;
        for (int k = 0; k < 3; ++k) dot += r[i * 3 + k] * r[j * 3 + k];
        if (std::abs(dot - (i == j ? 1.0 : 0.0)) > tol) return false;
      }
    }
    const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                       r[2] * (r[3] * r[7] - r[4] * r[6]);
    return det > 0.0;
  }

  void visit(Visitor& v) {
    v.field("R_b_c", R_b_c, {"-", -1.0, 1.0, "camera-to-body rotation, 3x3 row-major"});
    v.field("t_b_c_m", t_b_c_m, {"m", -10.0, 10.0, "camera origin in the body frame"});
    v.require(rotation_is_proper(), "R_b_c", "must be a proper rotation (orthonormal, det +1)");
  }
};

}  // namespace vigs::config
