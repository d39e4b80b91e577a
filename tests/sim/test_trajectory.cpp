#include <gtest/gtest.h>

#include <cmath>

#include "sim/floor_plan.hpp"
#include "sim/spline_trajectory.hpp"
#include "tests/sim/derivative_check.hpp"

namespace vigs::sim {
namespace {

TEST(SplineTrajectory, AnalyticDerivativesMatchFiniteDifferences) {
  const Scene s = make_preset("office", 3);
  const SplineTrajectory traj(s.route);
  test::expect_analytic_derivatives(traj, 1.5, 120.0, 3.7, 1e-4, {});
}

TEST(SplineTrajectory, DynamicallyPlausibleLongAndRevisiting) {
  for (const char* preset : {"office", "apartment"}) {
    const Scene s = make_preset(preset, 1);
    const SplineTrajectory traj(s.route);
    double v_max = 0, yaw_rate_max = 0, length = 0;
    Eigen::Vector3d prev = traj.state(0).p_w_m;
    for (double t = 0; t <= traj.duration_s(); t += 0.005) {
      const BodyState st = traj.state(t);
      v_max = std::max(v_max, st.v_w_mps.norm());
      // Yaw rate: rotation rate about the world vertical.
      yaw_rate_max = std::max(yaw_rate_max, std::abs((st.R_w_b * st.omega_b_rps).z()));
      length += (st.p_w_m - prev).norm();
      prev = st.p_w_m;
    }
    EXPECT_LE(v_max, 1.5) << preset;
    EXPECT_GT(v_max, 1.0) << preset;
    EXPECT_LE(yaw_rate_max, M_PI / 2) << preset;
    EXPECT_GT(length, std::string(preset) == "office" ? 350.0 : 120.0) << preset;
    // At rest for the first second.
    EXPECT_LT(traj.state(0.5).v_w_mps.norm(), 1e-12);
    // A revisit: after the first loop the route comes back within 0.5 m of its start.
    const Eigen::Vector3d start = traj.state(2.0).p_w_m;
    bool revisited = false;
    for (double t = 30.0; t < traj.duration_s(); t += 0.05) {
      revisited = revisited || (traj.state(t).p_w_m - start).norm() < 0.5;
    }
    EXPECT_TRUE(revisited) << preset;
  }
}

TEST(SplineTrajectory, StaysOnCorridorCentreLines) {
  const FloorPlanParams p = office_params();
  const Scene s = generate_floor_plan(p, 5);
  EXPECT_GE(s.size_x_m, 50.0);
  const SplineTrajectory traj(s.route);
  for (double t = 0; t <= traj.duration_s(); t += 0.1) {
    const Eigen::Vector3d q = traj.state(t).p_w_m;
    double off = 1e9;  // distance to the nearest corridor centre line
    for (double c : p.corridor_centers_m)
      off = std::min({off, std::abs(q.x() - c), std::abs(q.y() - c)});
    EXPECT_LT(off, 0.35) << t;  // corners are cut by at most ~0.28 m
  }
}

TEST(FloorPlan, DeterministicAndSeedDependent) {
  const Scene a = make_preset("office", 7), b = make_preset("office", 7),
              c = make_preset("office", 8);
  ASSERT_EQ(a.boxes.size(), b.boxes.size());
  for (std::size_t i = 0; i < a.boxes.size(); ++i) {
    EXPECT_EQ(a.boxes[i].box.lo.x, b.boxes[i].box.lo.x);
    EXPECT_EQ(a.boxes[i].tint, b.boxes[i].tint);
  }
  bool differs = a.boxes.size() != c.boxes.size();
  for (std::size_t i = 0; !differs && i < a.boxes.size(); ++i) {
    differs = a.boxes[i].box.lo.x != c.boxes[i].box.lo.x;
  }
  EXPECT_TRUE(differs);
  EXPECT_GT(a.boxes.size(), 300u);  // rooms, doors and furniture
  EXPECT_THROW(make_preset("castle", 1), std::invalid_argument);
}

}  // namespace
}  // namespace vigs::sim
