#pragma once
// The k best neighbour candidates of one query so far, sorted nearest first, in the caller's
// arrays (insertion sort: k is small). Candidates no closer than `worst` are refused, so the
// k-th distance is the pruning bound of every kNN search here; a tie keeps the candidate met
// first, which makes each search's result deterministic.
#include <cstdint>
#include <limits>

namespace vigs::tracking {

struct KnnList {
  int k = 0;
  int count = 0;
  std::uint32_t* indices = nullptr;
  float* sq_dists = nullptr;
  float worst = std::numeric_limits<float>::infinity();

  void offer(std::uint32_t index, float d2) {
    if (d2 >= worst) {
      return;
    }
    int i = count < k ? count++ : k - 1;
    while (i > 0 && sq_dists[i - 1] > d2) {
      sq_dists[i] = sq_dists[i - 1];
      indices[i] = indices[i - 1];
      --i;
    }
    sq_dists[i] = d2;
    indices[i] = index;
    if (count == k) {
      worst = sq_dists[k - 1];
    }
  }
};

}  // namespace vigs::tracking
