#pragma once
// Checks a trajectory's analytic velocity, acceleration and body rate against central finite
// differences of its position, velocity and orientation (step h), for the trajectory tests.
#include <gtest/gtest.h>

#include "core/geometry/so3.hpp"
#include "sim/trajectory.hpp"

namespace vigs::sim::test {

struct DerivativeTolerance {
  double v_mps = 1e-6, a_mps2 = 1e-5, omega_rps = 1e-6;
};

/// Samples t = t0, t0 + step, ... below t1.
inline void expect_analytic_derivatives(const Trajectory& traj, double t0, double t1, double step,
                                        double h, const DerivativeTolerance& tol) {
  for (double t = t0; t < t1; t += step) {
    const BodyState st = traj.state(t);
    const BodyState a = traj.state(t - h), b = traj.state(t + h);
    EXPECT_LT((st.v_w_mps - (b.p_w_m - a.p_w_m) / (2 * h)).norm(), tol.v_mps) << t;
    EXPECT_LT((st.a_w_mps2 - (b.v_w_mps - a.v_w_mps) / (2 * h)).norm(), tol.a_mps2) << t;
    const Eigen::Vector3d omega_fd =
        geometry::so3_log<double>(a.R_w_b.transpose() * b.R_w_b) / (2 * h);
    EXPECT_LT((st.omega_b_rps - omega_fd).norm(), tol.omega_rps) << t;
  }
}

}  // namespace vigs::sim::test
