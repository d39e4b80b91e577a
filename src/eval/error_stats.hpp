#pragma once
// Summary statistics of a list of errors. `rmse` is the root of the mean of the squared
// errors. (GS-ICP SLAM and SplaTAM print the *mean* error under the name "ATE RMSE"; compare
// their figures with `mean`.)
#include <string>
#include <vector>

#include "io/json_text.hpp"

namespace vigs::eval {

struct ErrorStats {
  std::size_t count = 0;
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;  ///< middle value; mean of the two middle values for an even count
  double std = 0.0;     ///< population standard deviation
  double min = 0.0;
  double max = 0.0;
  double sse = 0.0;  ///< sum of squared errors
};

ErrorStats compute_stats(std::vector<double> errors);

/// Adds "rmse", "mean", "median", "std", "min", "max", "sse" to the object `j`.
void add_stats_fields(io::Json& j, const ErrorStats& s);

}  // namespace vigs::eval
