#include "eval/error_stats.hpp"

#include <algorithm>
#include <cmath>

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

void add_stats_fields(io::Json& j, const ErrorStats& s) {
  j["rmse"] = s.rmse;
  j["mean"] = s.mean;
  j["median"] = s.median;
  j["std"] = s.std;
  j["min"] = s.min;
  j["max"] = s.max;
  j["sse"] = s.sse;
}

}  // namespace vigs::eval
