#pragma once
// RMS accumulators of the gyro-bias drift benchmarks (bench_inertial_drift.cpp on analytic and
// EuRoC motion, bench_inertial_sim.cpp on the simulator): per-frame guess error, 1 s IMU-only
// drift and gyro-bias error, reported as the same Google Benchmark counters everywhere.
#include <benchmark/benchmark.h>

#include <cmath>

#include "core/geometry/se3.hpp"

namespace vigs::bench {

struct DriftStats {
  double guess_rot = 0, guess_pos = 0, drift_rot = 0, drift_pos = 0, bias_err = 0;
  int n_guess = 0, n_drift = 0;

  void add_guess(const geometry::PoseError& e) {
    guess_rot += e.rotation_rad * e.rotation_rad;
    guess_pos += e.translation_m * e.translation_m;
    ++n_guess;
  }
  void add_bias_error_sq(double err_sq) { bias_err += err_sq; }
  void add_drift(const geometry::PoseError& e) {
    drift_rot += e.rotation_rad * e.rotation_rad;
    drift_pos += e.translation_m * e.translation_m;
    ++n_drift;
  }

  /// Sets the counters; `guess_position` and `bias` say whether those were accumulated.
  void report(benchmark::State& state, bool guess_position, bool bias) const {
    const double deg = 180.0 / M_PI;
    state.counters["guess_rot_rms_deg"] = deg * std::sqrt(guess_rot / n_guess);
    if (guess_position) state.counters["guess_pos_rms_m"] = std::sqrt(guess_pos / n_guess);
    state.counters["drift1s_rot_rms_deg"] = deg * std::sqrt(drift_rot / n_drift);
    state.counters["drift1s_pos_rms_m"] = std::sqrt(drift_pos / n_drift);
    if (bias) state.counters["bias_err_rms_rps"] = std::sqrt(bias_err / n_guess);
  }
};

}  // namespace vigs::bench
