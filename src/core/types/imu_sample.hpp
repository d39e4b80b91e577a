#pragma once
#include <cstdint>

namespace vigs {

/// One IMU measurement in the IMU (body) frame, stamped on the host monotonic clock.
/// Trivially copyable so that it moves through rt rings without allocation.
struct ImuSample {
  std::int64_t t_ns = 0;      ///< host CLOCK_MONOTONIC (live) or recording time (replay), ns
  double gyro_rps[3] = {};    ///< angular rate, rad/s
  double accel_mps2[3] = {};  ///< specific force, m/s^2 (gravity included, as measured)
};

}  // namespace vigs
