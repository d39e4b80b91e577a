#include "sim/speed_profile.hpp"

#include <algorithm>
#include <stdexcept>

namespace vigs::sim {

void SpeedProfile::push(double r1, double seconds) {
  if (!(seconds > 0.0)) throw std::invalid_argument("speed profile: segment length must be > 0");
  const Segment s{t_end_, seconds, u_end_, rate_end_, r1};
  seg_.push_back(s);
  t_end_ += seconds;
  u_end_ = eval(s, t_end_).u;
  rate_end_ = r1;
}

void SpeedProfile::hold(double seconds) {
  push(rate_end_, seconds);
}

void SpeedProfile::ramp(double rate, double seconds) {
  if (rate < 0.0) throw std::invalid_argument("speed profile: negative rate");
  push(rate, seconds);
}

WarpPoint SpeedProfile::eval(const Segment& s, double t_s) {
  const double T = s.length_s;
  const double tau = std::clamp((t_s - s.t0_s) / T, 0.0, 1.0);
  const double d = s.r1 - s.r0;
  WarpPoint w;
  const double tau2 = tau * tau, tau3 = tau2 * tau;
  w.u = s.u0 + T * (s.r0 * tau + d * (tau3 - 0.5 * tau3 * tau));  // integral of the rate
  w.du = s.r0 + d * (3.0 * tau2 - 2.0 * tau3);
  w.ddu = d * (6.0 * tau - 6.0 * tau2) / T;
  w.dddu = d * (6.0 - 12.0 * tau) / (T * T);
  return w;
}

WarpPoint SpeedProfile::at(double t_s) const {
  if (seg_.empty() || t_s >= t_end_) return {u_end_, rate_end_, 0.0, 0.0};
  if (t_s <= 0.0) return eval(seg_.front(), 0.0);
  // The last segment starting at or before t.
  const auto it = std::upper_bound(seg_.begin(), seg_.end(), t_s,
                                   [](double t, const Segment& s) { return t < s.t0_s; });
  return eval(*(it - 1), t_s);
}

}  // namespace vigs::sim
