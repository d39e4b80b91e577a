#pragma once
// Linear interpolation of an IMU reading at a time between two samples, used to cut
// preintegration windows exactly at frame timestamps.
#include <cstdint>

#include "core/types/imu_sample.hpp"

namespace vigs::inertial {

/// Reading at t_ns on the straight line between a and b (a.t_ns <= t_ns <= b.t_ns). When the
/// two stamps coincide, or t_ns lies outside [a, b], the nearer sample's reading is held.
inline ImuSample interpolate_sample(const ImuSample& a, const ImuSample& b, std::int64_t t_ns) {
  ImuSample out;
  out.t_ns = t_ns;
  const std::int64_t span_ns = b.t_ns - a.t_ns;
  double w = 0.0;
  if (span_ns > 0) {
    w = static_cast<double>(t_ns - a.t_ns) / static_cast<double>(span_ns);
    w = w < 0.0 ? 0.0 : (w > 1.0 ? 1.0 : w);
  }
  for (int k = 0; k < 3; ++k) {
    out.gyro_rps[k] = a.gyro_rps[k] + w * (b.gyro_rps[k] - a.gyro_rps[k]);
    out.accel_mps2[k] = a.accel_mps2[k] + w * (b.accel_mps2[k] - a.accel_mps2[k]);
  }
  return out;
}

}  // namespace vigs::inertial
