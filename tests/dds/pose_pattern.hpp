#pragma once
// The deterministic pose stream the DDS tests publish and check (also from the Cyclone DDS
// reader, which shares no code with the publisher but this pattern). Sample i:
//   t_ns = kT0Ns + i * 50 ms (20 Hz sensor time; far from any publish time)
//   position (0.01 i, 1 + 0.5 i, -2), rotation about z by 0.01 i rad,
//   covariance[k] = 1e-4 (k + 1) + 1e-9 i (every entry distinct: a transposed or shifted layout
//   fails the check), velocity (0.1, 0.2, 0.3) in the world, angular rate (0, 0, 0.2) in camera,
//   keyframe every 10th sample, source i % 4 (each PoseSource in turn), flags i % 128 (every
//   combination of the seven PoseFlags bits in 128 samples; each bit by sample 64).
#include <cmath>
#include <cstdint>

#include "core/types/pose_sample.hpp"

namespace vigs::dds::test {

inline constexpr std::int64_t kT0Ns = 1'700'000'000'123'456'789;
inline constexpr std::int64_t kPeriodNs = 50'000'000;

inline PoseSample pattern_sample(std::uint64_t i) {
  PoseSample s;
  const double di = static_cast<double>(i);
  s.t_ns = kT0Ns + static_cast<std::int64_t>(i) * kPeriodNs;
  s.frame_index = i;
  s.p_w_m[0] = 0.01 * di;
  s.p_w_m[1] = 1.0 + 0.5 * di;
  s.p_w_m[2] = -2.0;
  const double half = 0.5 * 0.01 * di;
  s.q_w_xyzw[0] = 0;
  s.q_w_xyzw[1] = 0;
  s.q_w_xyzw[2] = std::sin(half);
  s.q_w_xyzw[3] = std::cos(half);
  for (int k = 0; k < 36; ++k) s.covariance[k] = 1e-4 * (k + 1) + 1e-9 * di;
  s.v_w_mps[0] = 0.1;
  s.v_w_mps[1] = 0.2;
  s.v_w_mps[2] = 0.3;
  s.omega_c_radps[2] = 0.2;
  s.keyframe = i % 10 == 0;
  s.source = static_cast<PoseSource>(i % 4);
  s.flags = static_cast<std::uint32_t>(i % 128);
  return s;
}

/// Index of the pattern sample stamped t_ns, or -1.
inline std::int64_t pattern_index(std::int64_t t_ns) {
  const std::int64_t d = t_ns - kT0Ns;
  if (d < 0 || d % kPeriodNs != 0) return -1;
  return d / kPeriodNs;
}

}  // namespace vigs::dds::test
