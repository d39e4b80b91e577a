#include "pipeline/steady_rate.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace vigs::pipeline {
namespace {

/// The first and last frame of the steady window: `trim` of the n frames cut at each end (the
/// last after the first). Nothing with fewer than 3 frames or trim outside [0, 0.5).
std::optional<std::pair<std::size_t, std::size_t>> steady_window(std::size_t n, double trim) {
  if (n < 3 || !(trim >= 0.0 && trim < 0.5)) return std::nullopt;
  const auto a = static_cast<std::size_t>(std::floor(trim * static_cast<double>(n - 1)));
  return std::pair{a, std::max(a + 1, n - 1 - a)};
}

}  // namespace

std::optional<double> steady_real_time_factor(const std::vector<std::int64_t>& stream_ns,
                                              const std::vector<std::int64_t>& done_ns,
                                              double trim) {
  const auto window = steady_window(stream_ns.size(), trim);
  if (!window || done_ns.size() != stream_ns.size()) return std::nullopt;
  const auto [a, b] = *window;
  const std::int64_t wall = done_ns[b] - done_ns[a];
  if (wall <= 0) return std::nullopt;
  return static_cast<double>(stream_ns[b] - stream_ns[a]) / static_cast<double>(wall);
}

std::optional<std::uint64_t> events_in_steady_window(const std::vector<std::int64_t>& done_ns,
                                                     std::span<const std::int64_t> event_ns,
                                                     double trim) {
  const auto window = steady_window(done_ns.size(), trim);
  if (!window) return std::nullopt;
  const std::int64_t from_ns = done_ns[window->first], to_ns = done_ns[window->second];
  return static_cast<std::uint64_t>(std::count_if(
      event_ns.begin(), event_ns.end(), [&](auto t) { return t > from_ns && t <= to_ns; }));
}

}  // namespace vigs::pipeline
