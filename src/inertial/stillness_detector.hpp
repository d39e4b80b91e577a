#pragma once
// Whether the IMU was at rest over a stretch of time: the test statistic of a zero-velocity
// detector, for the fused filter's zero-velocity update (inertial_frontend.hpp).
//
// Over the N samples of the window, with the accelerometer's per-sample noise sigma s_a (noise
// density times sqrt(rate)),
//   T = 1/N sum_k |a_k - mean(a)|^2 / s_a^2,
// the accelerometer's spread about its own mean: about 3 (three degrees of freedom) for a body at
// rest, and far above for a moving one (a 2 cm step bob at 1.7 Hz alone swings the
// accelerometer by ~2 m/s^2 against a noise of ~0.03 m/s^2; a tilt of 1 deg moves gravity's
// reading by 0.17 m/s^2). It is the accelerometer half of the SHOE detector of Skog et al.
// ("Zero-velocity detection - an algorithm evaluation", IEEE TBME 2010), with the mean in place
// of gravity's known magnitude, so an accelerometer bias or a gravity constant a little off does
// not read as motion. The gyro half is left out on purpose: the update measures the body's
// velocity, which a turn on the spot does not change, and the simulated carrier's standstills
// yaw by a few deg/s (gyro term 100-500 at rest, accelerometer term 2.6-5.5; BENCHMARKS.md,
// thirty-third session). Like every IMU-only test it cannot tell rest from a perfectly even
// glide, so its user gates the update on the filter's own velocity as well.
//
// Samples go into a ring allocated at construction; nothing allocates, locks or logs after it.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>

#include "core/history_ring.hpp"
#include "core/types/imu_sample.hpp"

namespace vigs::inertial {

struct StillnessOptions {
  double window_s = 0.2;        ///< the statistic looks back at least this far
  double accel_sigma_mps2 = 0;  ///< per-sample white-noise sigma of the accelerometer
  int capacity = 2048;          ///< samples kept: the longest stretch that can be judged
};

class StillnessDetector {
 public:
  explicit StillnessDetector(const StillnessOptions& options)
      : options_(options), ring_(static_cast<std::size_t>(std::max(2, options.capacity))) {}

  /// Appends one sample (the caller passes them in time order); the oldest falls off when full.
  void add(const ImuSample& s) { ring_.push_back(s); }

  /// T over the samples in [min(t_from_ns, t_to_ns - window), t_to_ns]. nullopt when the kept
  /// samples do not reach back to that start (too few yet, or a stretch longer than the ring)
  /// or the sigma is not positive.
  [[nodiscard]] std::optional<double> statistic(std::int64_t t_from_ns,
                                                std::int64_t t_to_ns) const {
    if (!(options_.accel_sigma_mps2 > 0.0) || ring_.size() < 2) return std::nullopt;
    const auto window_ns = static_cast<std::int64_t>(options_.window_s * 1e9);
    const std::int64_t t_start = std::min(t_from_ns, t_to_ns - window_ns);
    if (ring_.front().t_ns > t_start) return std::nullopt;
    Eigen::Vector3d sum_a = Eigen::Vector3d::Zero();
    double sum_aa = 0.0;
    int n = 0;
    for (std::size_t i = 0; i < ring_.size(); ++i) {
      const ImuSample& s = ring_[i];
      if (s.t_ns < t_start) continue;
      if (s.t_ns > t_to_ns) break;
      const Eigen::Vector3d a(s.accel_mps2[0], s.accel_mps2[1], s.accel_mps2[2]);
      sum_a += a;
      sum_aa += a.squaredNorm();
      ++n;
    }
    if (n < 2) return std::nullopt;
    // sum |a_k - mean|^2 = sum |a_k|^2 - |sum a|^2 / n (the window's values are O(10) m/s^2, so
    // the cancellation costs ~1e-14 relative: far below the noise this measures).
    const double spread_aa = std::max(0.0, sum_aa - sum_a.squaredNorm() / n);
    const double sa2 = options_.accel_sigma_mps2 * options_.accel_sigma_mps2;
    const double t = spread_aa / sa2 / n;
    return std::isfinite(t) ? std::optional<double>(t) : std::nullopt;
  }

 private:
  StillnessOptions options_;
  HistoryRing<ImuSample> ring_;
};

}  // namespace vigs::inertial
