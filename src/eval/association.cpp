#include "eval/association.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

namespace vigs::eval {

std::vector<IndexPair> associate(const std::vector<double>& t_a_s, const std::vector<double>& t_b_s,
                                 double max_difference_s, double offset_s) {
  // Candidates through a sorted view of b: only stamps inside the window can match, so the
  // O(|a| |b|) scan of the reference script becomes O(|a| log |b| + candidates).
  std::vector<std::size_t> b_order(t_b_s.size());
  std::iota(b_order.begin(), b_order.end(), std::size_t{0});
  std::stable_sort(b_order.begin(), b_order.end(),
                   [&](std::size_t x, std::size_t y) { return t_b_s[x] < t_b_s[y]; });
  std::vector<double> b_shifted(t_b_s.size());
  for (std::size_t k = 0; k < b_order.size(); ++k) b_shifted[k] = t_b_s[b_order[k]] + offset_s;

  struct Candidate {
    double dt;
    double ta;
    double tb;
    std::size_t a;
    std::size_t b;
  };
  std::vector<Candidate> candidates;
  for (std::size_t a = 0; a < t_a_s.size(); ++a) {
    const double ta = t_a_s[a];
    auto it = std::lower_bound(b_shifted.begin(), b_shifted.end(), ta - max_difference_s);
    for (; it != b_shifted.end() && *it <= ta + max_difference_s; ++it) {
      const double dt = std::abs(ta - *it);
      if (!(dt < max_difference_s)) continue;
      const std::size_t b = b_order[static_cast<std::size_t>(it - b_shifted.begin())];
      candidates.push_back({dt, ta, t_b_s[b], a, b});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    return std::tie(x.dt, x.ta, x.tb, x.a, x.b) < std::tie(y.dt, y.ta, y.tb, y.a, y.b);
  });
  std::vector<char> used_a(t_a_s.size(), 0), used_b(t_b_s.size(), 0);
  std::vector<IndexPair> matches;
  for (const auto& c : candidates) {
    if (used_a[c.a] || used_b[c.b]) continue;
    used_a[c.a] = used_b[c.b] = 1;
    matches.push_back({c.a, c.b});
  }
  std::sort(matches.begin(), matches.end(), [&](const IndexPair& x, const IndexPair& y) {
    return std::tie(t_a_s[x.a], x.a) < std::tie(t_a_s[y.a], y.a);
  });
  return matches;
}

}  // namespace vigs::eval
