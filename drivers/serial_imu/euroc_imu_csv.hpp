// Reader of EuRoC-format IMU CSV files (`t[ns], w_x, w_y, w_z [rad/s], a_x, a_y, a_z [m/s^2]`,
// '#' comment lines), the source `vigs imu play` turns into serial wire bytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace vigs::drivers {

struct ImuCsvRow {
  std::int64_t t_ns = 0;
  double gyro_rps[3] = {};
  double accel_mps2[3] = {};
  int line = 0;  ///< 1-based line in the file
};

/// All rows of `path`. Throws std::runtime_error naming the file and line for an unreadable file,
/// a malformed number, a value that is not finite (nan, inf), a wrong column count or a
/// timestamp that does not increase.
[[nodiscard]] std::vector<ImuCsvRow> read_euroc_imu_csv(const std::string& path);

}  // namespace vigs::drivers
