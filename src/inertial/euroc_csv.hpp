#pragma once
// Readers for the EuRoC MAV dataset's CSV files (ASL format), so that users can check their
// own recordings with `vigs eval imu`:
//   imu0/data.csv:  t[ns], w_x, w_y, w_z [rad/s], a_x, a_y, a_z [m/s^2]
//   state_groundtruth_estimate0/data.csv: t[ns], p xyz [m], q w x y z, v xyz [m/s],
//                   b_w xyz [rad/s], b_a xyz [m/s^2]  (body = IMU frame, pose in world)
// Lines starting with '#' and blank lines are skipped. Any malformed line is an error that
// names the file, the line number and the field; stamps must strictly increase.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/types/imu_sample.hpp"

namespace vigs::inertial {

class EurocCsvError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct GroundTruthState {
  std::int64_t t_ns = 0;
  Eigen::Vector3d p_w_b_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond q_w_b = Eigen::Quaterniond::Identity();  ///< normalised on read
  Eigen::Vector3d v_w_b_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d bias_gyro_rps = Eigen::Vector3d::Zero();
  Eigen::Vector3d bias_accel_mps2 = Eigen::Vector3d::Zero();
};

/// Throws EurocCsvError on an unreadable file or a malformed line.
std::vector<ImuSample> read_euroc_imu_csv(const std::string& path);
std::vector<GroundTruthState> read_euroc_groundtruth_csv(const std::string& path);

/// The same parsers on text already in memory; `name` is used in error messages.
std::vector<ImuSample> parse_euroc_imu_csv(const std::string& text, const std::string& name);
std::vector<GroundTruthState> parse_euroc_groundtruth_csv(const std::string& text,
                                                          const std::string& name);

}  // namespace vigs::inertial
