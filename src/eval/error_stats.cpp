#include "eval/error_stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace vigs::eval {

ErrorStats compute_stats(std::vector<double> errors) {
  ErrorStats s;
  s.count = errors.size();
  if (errors.empty()) return s;
  double sum = 0.0, sq = 0.0;
  for (double e : errors) {
    sum += e;
    sq += e * e;
  }
  const double n = static_cast<double>(errors.size());
  s.mean = sum / n;
  s.sse = sq;
  s.rmse = std::sqrt(sq / n);
  double var = 0.0;
  for (double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(var / n);
  std::sort(errors.begin(), errors.end());
  s.min = errors.front();
  s.max = errors.back();
  const std::size_t mid = errors.size() / 2;
  s.median = errors.size() % 2 ? errors[mid] : 0.5 * (errors[mid - 1] + errors[mid]);
  return s;
}

std::string stats_json_fields(const ErrorStats& s) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "\"rmse\": %.17g, \"mean\": %.17g, \"median\": %.17g, \"std\": %.17g, "
                "\"min\": %.17g, \"max\": %.17g, \"sse\": %.17g",
                s.rmse, s.mean, s.median, s.std, s.min, s.max, s.sse);
  return buf;
}

}  // namespace vigs::eval
