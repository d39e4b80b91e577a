#include "pipeline/steady_rate.hpp"

#include <algorithm>
#include <cmath>

namespace vigs::pipeline {

std::optional<double> steady_real_time_factor(const std::vector<std::int64_t>& stream_ns,
                                              const std::vector<std::int64_t>& done_ns,
                                              double trim) {
  const std::size_t n = stream_ns.size();
  if (n < 3 || done_ns.size() != n || !(trim >= 0.0 && trim < 0.5)) return std::nullopt;
  const auto a = static_cast<std::size_t>(std::floor(trim * static_cast<double>(n - 1)));
  const std::size_t b = std::max(a + 1, n - 1 - a);
  const std::int64_t wall = done_ns[b] - done_ns[a];
  if (wall <= 0) return std::nullopt;
  return static_cast<double>(stream_ns[b] - stream_ns[a]) / static_cast<double>(wall);
}

std::optional<std::uint64_t> events_in_steady_window(const std::vector<std::int64_t>& done_ns,
                                                     std::span<const std::int64_t> event_ns,
                                                     double trim) {
  const std::size_t n = done_ns.size();
  if (n < 3 || !(trim >= 0.0 && trim < 0.5)) return std::nullopt;
  const auto a = static_cast<std::size_t>(std::floor(trim * static_cast<double>(n - 1)));
  const std::size_t b = std::max(a + 1, n - 1 - a);
  return static_cast<std::uint64_t>(std::count_if(
      event_ns.begin(), event_ns.end(), [&](auto t) { return t > done_ns[a] && t <= done_ns[b]; }));
}

}  // namespace vigs::pipeline
