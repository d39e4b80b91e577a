#pragma once
// TUM RGB-D benchmark association (associate.py / evaluate_ate.py): every pair (a, b) with
// |t_a - (t_b + offset)| < max_difference is a candidate; candidates are taken greedily in
// increasing |dt| (ties: earlier t_a, then earlier t_b) and each stamp is used at most once.
// The result is sorted by t_a.
#include <cstddef>
#include <vector>

namespace vigs::eval {

struct IndexPair {
  std::size_t a = 0;  ///< index into the first (reference) list
  std::size_t b = 0;  ///< index into the second (estimate) list
};

std::vector<IndexPair> associate(const std::vector<double>& t_a_s, const std::vector<double>& t_b_s,
                                 double max_difference_s, double offset_s = 0.0);

}  // namespace vigs::eval
