// ClockMapper: maps device time to host CLOCK_MONOTONIC with a drift-tracking fit of the lower
// envelope of receive times.
//
// Model: a sample taken at device time d reaches the host at h = a + (1 + drift) d + latency,
// with latency >= L_min > 0 (USB / UART transfer only ever adds delay). So each observation gives
// an upper bound c = h - (1 + drift) d on the offset a + L_min, and the best estimate is the lower
// envelope of those bounds:
//  - Offset (after Olson, "A passive solution to the sensor synchronization problem", 2010): it
//    drops at once to any lower bound, and otherwise may rise only at `offset_creep_ppm`, which
//    lets it follow a residual drift error while latency spikes cannot drag it up.
//  - Drift: every `envelope_window_ns` of device time, the observation with the smallest bound
//    becomes one envelope point; an exponentially weighted least-squares line through those points
//    gives the drift (clamped to +-max_drift_ppm). When the drift estimate changes, the offset is
//    re-anchored so the mapping stays continuous at the current device time: stamps never jump.
// The result tracks true sample time plus the (unobservable, constant) minimum latency. Limit: the
// fitted drift lags a changing drift by about 16 s times its rate of change, and the offset
// absorbs a lag up to offset_creep_ppm, so drift changes up to ~0.6 ppm/s are followed (crystal
// warm-up is orders of magnitude slower).
// All state is fixed-size; observe() and map() never allocate.
#pragma once

#include <cstdint>

namespace vigs::drivers {

struct ClockMapperSettings {
  double max_drift_ppm = 1000.0;    ///< |device vs host rate error| accepted from the fit
  double warmup_creep_ppm = 300.0;  ///< offset rise rate before the drift is fitted
  double offset_creep_ppm = 10.0;   ///< offset rise rate once the drift is fitted
  std::int64_t envelope_window_ns = 250'000'000;  ///< device time per envelope point
  double fit_forgetting = 0.97;  ///< weight kept per window (memory ~ 1/(1-f) windows)
  int min_fit_windows = 4;       ///< envelope points before the drift is trusted
};

class ClockMapper {
 public:
  explicit ClockMapper(const ClockMapperSettings& settings = {}) : s_(settings) {}

  void reset() noexcept;

  /// A sample of device time `device_ns` (any origin, increasing) had arrived by host `host_ns`.
  void observe(std::int64_t device_ns, std::int64_t host_ns) noexcept;

  /// Host time of device time `device_ns`. Valid after the first observe().
  [[nodiscard]] std::int64_t map(std::int64_t device_ns) const noexcept;

  [[nodiscard]] bool initialised() const noexcept { return initialised_; }
  [[nodiscard]] bool drift_fitted() const noexcept { return windows_ >= s_.min_fit_windows; }
  [[nodiscard]] double drift_ppm() const noexcept { return drift_ * 1e6; }
  [[nodiscard]] std::int64_t observations() const noexcept { return observations_; }

 private:
  void close_window(double x_now) noexcept;

  ClockMapperSettings s_;
  bool initialised_ = false;
  std::int64_t device0_ns_ = 0;  // origins: x = device - device0, y = host - host0 (ns, double)
  std::int64_t host0_ns_ = 0;
  double offset_ns_ = 0.0;  // mapped(x) = host0 + offset + (1 + drift) x
  double drift_ = 0.0;
  double last_x_ = 0.0;
  std::int64_t observations_ = 0;
  // Current envelope window.
  double window_start_x_ = 0.0;
  double window_min_r_ = 0.0;  // min of (y - x) in the window
  double window_min_x_ = 0.0;
  bool window_has_point_ = false;
  // Weighted sums of envelope points (x in s, r = y - x in ns).
  int windows_ = 0;
  double sw_ = 0.0, sx_ = 0.0, sr_ = 0.0, sxx_ = 0.0, sxr_ = 0.0;
};

}  // namespace vigs::drivers
