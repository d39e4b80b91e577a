#pragma once
// A time warp u(t) of a path parameter with a designed rate profile: cruising, slow zones,
// standstills, and smooth ramps between them. Each ramp changes the rate with the cubic
// smoothstep S(tau) = 3 tau^2 - 2 tau^3, so du/dt is C1 and d2u/dt2 is continuous; u and its
// first three time derivatives are exact polynomials (no numerical integration).
#include <vector>

namespace vigs::sim {

/// u and its time derivatives at one time (u in path units, t in seconds).
struct WarpPoint {
  double u = 0.0;
  double du = 0.0;    ///< du/dt
  double ddu = 0.0;   ///< d2u/dt2
  double dddu = 0.0;  ///< d3u/dt3 (piecewise continuous)
};

class SpeedProfile {
 public:
  /// Starts at rest at `u0` at t = 0.
  explicit SpeedProfile(double u0) : u_end_(u0) {}

  /// Holds the current rate (which must be > 0 unless `seconds` is a dwell) for `seconds`.
  void hold(double seconds);
  /// Ramps the rate from the current one to `rate` over `seconds` (> 0).
  void ramp(double rate, double seconds);

  [[nodiscard]] WarpPoint at(double t_s) const;
  [[nodiscard]] double duration_s() const { return t_end_; }
  [[nodiscard]] double u_end() const { return u_end_; }
  [[nodiscard]] double rate() const { return rate_end_; }

 private:
  struct Segment {
    double t0_s, length_s, u0, r0, r1;
  };
  [[nodiscard]] static WarpPoint eval(const Segment& s, double t_s);
  void push(double r1, double seconds);

  std::vector<Segment> seg_;
  double t_end_ = 0.0, u_end_ = 0.0, rate_end_ = 0.0;
};

}  // namespace vigs::sim
