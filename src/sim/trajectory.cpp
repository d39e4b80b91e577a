#include "sim/trajectory.hpp"

#include <Eigen/Geometry>
#include <cmath>

namespace vigs::sim {

void set_attitude(const EulerZyx& e, BodyState& st) {
  st.R_w_b = (Eigen::AngleAxisd(e.yaw, Eigen::Vector3d::UnitZ()) *
              Eigen::AngleAxisd(e.pitch, Eigen::Vector3d::UnitY()) *
              Eigen::AngleAxisd(e.roll, Eigen::Vector3d::UnitX()))
                 .toRotationMatrix();
  const double sp = std::sin(e.pitch), cp = std::cos(e.pitch);
  const double sr = std::sin(e.roll), cr = std::cos(e.roll);
  st.omega_b_rps =
      Eigen::Vector3d(e.roll_rate - e.yaw_rate * sp, e.pitch_rate * cr + e.yaw_rate * cp * sr,
                      -e.pitch_rate * sr + e.yaw_rate * cp * cr);
}

}  // namespace vigs::sim
