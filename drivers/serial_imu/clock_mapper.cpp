#include "drivers/serial_imu/clock_mapper.hpp"

#include <algorithm>
#include <cmath>

namespace vigs::drivers {

void ClockMapper::reset() noexcept {
  *this = ClockMapper(s_);
}

void ClockMapper::observe(std::int64_t device_ns, std::int64_t host_ns) noexcept {
  if (!initialised_) {
    initialised_ = true;
    device0_ns_ = device_ns;
    host0_ns_ = host_ns;
    offset_ns_ = 0.0;
    last_x_ = 0.0;
    window_start_x_ = 0.0;
  }
  ++observations_;
  const double x = static_cast<double>(device_ns - device0_ns_);
  const double y = static_cast<double>(host_ns - host0_ns_);

  // Offset: lower envelope with a bounded rise rate.
  const double bound = y - (1.0 + drift_) * x;
  const double creep = (drift_fitted() ? s_.offset_creep_ppm : s_.warmup_creep_ppm) * 1e-6;
  const double dx = std::max(0.0, x - last_x_);
  offset_ns_ = std::min(bound, offset_ns_ + creep * dx);
  last_x_ = std::max(last_x_, x);

  // Drift: one envelope point per window of device time.
  if (x - window_start_x_ >= static_cast<double>(s_.envelope_window_ns) && window_has_point_) {
    close_window(x);
    window_start_x_ = x;
    window_has_point_ = false;
  }
  const double r = y - x;
  if (!window_has_point_ || r < window_min_r_) {
    window_min_r_ = r;
    window_min_x_ = x;
    window_has_point_ = true;
  }
}

void ClockMapper::close_window(double x_now) noexcept {
  const double f = s_.fit_forgetting;
  const double xs = window_min_x_ * 1e-9;  // seconds keep the sums well conditioned
  sw_ = f * sw_ + 1.0;
  sx_ = f * sx_ + xs;
  sr_ = f * sr_ + window_min_r_;
  sxx_ = f * sxx_ + xs * xs;
  sxr_ = f * sxr_ + xs * window_min_r_;
  ++windows_;
  if (!drift_fitted()) return;
  const double mean_x = sx_ / sw_;
  const double var_x = sxx_ / sw_ - mean_x * mean_x;
  if (!(var_x > 0.0)) return;
  const double cov_xr = sxr_ / sw_ - mean_x * (sr_ / sw_);
  const double slope_ns_per_s = cov_xr / var_x;  // residual ns per device second
  const double limit = s_.max_drift_ppm * 1e-6;
  const double new_drift = std::clamp(slope_ns_per_s * 1e-9, -limit, limit);
  // Keep mapped(x_now) unchanged: offset + (1 + d_old) x = offset' + (1 + d_new) x.
  offset_ns_ += (drift_ - new_drift) * x_now;
  drift_ = new_drift;
}

std::int64_t ClockMapper::map(std::int64_t device_ns) const noexcept {
  const double x = static_cast<double>(device_ns - device0_ns_);
  return host0_ns_ + static_cast<std::int64_t>(std::llround(offset_ns_ + (1.0 + drift_) * x));
}

}  // namespace vigs::drivers
