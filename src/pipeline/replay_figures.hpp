#pragma once
// Per-run figures of a replay computed the same way wherever they are reported (stats.json,
// bench_pipeline, tests): the tracking time's quantiles and the mean GICP iterations.
#include <algorithm>
#include <cstddef>
#include <optional>
#include <vector>

#include "pipeline/lockstep_replay.hpp"

namespace vigs::pipeline {

/// The q-quantile (0..1) of `values`, nearest rank rounded to the closest index: the rule of
/// every per-frame figure reported (tracking time, pose latency); none when empty.
template <class T>
std::optional<T> nearest_rank_quantile(std::vector<T> values, double q) {
  if (values.empty()) return std::nullopt;
  const auto k = static_cast<std::size_t>(q * static_cast<double>(values.size() - 1) + 0.5);
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}

/// The q-quantile of the per-frame tracking time in ms; none without frames.
inline std::optional<double> track_ms_quantile(const ReplayResult& r, double q) {
  const std::optional<float> ms = nearest_rank_quantile(r.track_ms, q);
  return ms ? std::optional<double>(*ms) : std::nullopt;
}

/// GICP iterations per frame over every frame after the first (the first only starts the
/// map); none with fewer than two frames.
inline std::optional<double> mean_gicp_iterations(const ReplayResult& r) {
  if (r.frames.size() < 2) return std::nullopt;
  long sum = 0;
  for (std::size_t i = 1; i < r.frames.size(); ++i) sum += r.frames[i].gicp_iterations;
  return static_cast<double>(sum) / static_cast<double>(r.frames.size() - 1);
}

}  // namespace vigs::pipeline
