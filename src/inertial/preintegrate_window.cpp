#include "inertial/preintegrate_window.hpp"

#include <algorithm>

#include "inertial/imu_interpolation.hpp"

namespace vigs::inertial {

namespace {
// Index of the last sample with t_ns <= t (samples.size() if none).
std::size_t last_at_or_before(std::span<const ImuSample> samples, std::int64_t t) {
  const auto it = std::upper_bound(samples.begin(), samples.end(), t,
                                   [](std::int64_t v, const ImuSample& s) { return v < s.t_ns; });
  if (it == samples.begin()) return samples.size();
  return static_cast<std::size_t>(it - samples.begin()) - 1;
}
}  // namespace

bool preintegrate_window(std::span<const ImuSample> samples, std::int64_t t_i_ns,
                         std::int64_t t_j_ns, const Eigen::Vector3d& bias_gyro_rps,
                         const Eigen::Vector3d& bias_accel_mps2, Preintegrator& pi) {
  if (samples.empty() || t_j_ns < t_i_ns) return false;
  if (samples.front().t_ns > t_i_ns || samples.back().t_ns < t_j_ns) return false;
  std::size_t k = last_at_or_before(samples, t_i_ns);
  const ImuSample start = (samples[k].t_ns == t_i_ns || k + 1 == samples.size())
                              ? interpolate_sample(samples[k], samples[k], t_i_ns)
                              : interpolate_sample(samples[k], samples[k + 1], t_i_ns);
  pi.reset(start, bias_gyro_rps, bias_accel_mps2);
  for (++k; k < samples.size() && samples[k].t_ns < t_j_ns; ++k) {
    if (samples[k].t_ns > pi.t_end_ns()) pi.integrate(samples[k]);
  }
  if (pi.t_end_ns() == t_j_ns) return true;
  return pi.integrate_until(t_j_ns, samples[k]);
}

std::int64_t largest_gap_ns(std::span<const ImuSample> samples, std::int64_t t_i_ns,
                            std::int64_t t_j_ns) {
  if (samples.empty() || samples.front().t_ns > t_i_ns || samples.back().t_ns < t_j_ns) return 0;
  std::int64_t gap = 0;
  for (std::size_t k = last_at_or_before(samples, t_i_ns);
       k + 1 < samples.size() && samples[k].t_ns < t_j_ns; ++k) {
    gap = std::max(gap, samples[k + 1].t_ns - samples[k].t_ns);
  }
  return gap;
}

}  // namespace vigs::inertial
