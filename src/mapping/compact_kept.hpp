#pragma once

#include <cstddef>
#include <vector>

namespace vigs::mapping {

/// Keeps, in order, the records of `v` whose `keep[i]` is true, where record i is the `stride`
/// elements starting at v[stride * i]; returns the number of records kept. Every array that
/// follows the map one record per Gaussian (parameters, Adam moments, anchors, far flags,
/// see-through counts) compacts through this, so a prune keeps them all aligned.
template <class T, class Mask>
std::size_t compact_kept(std::vector<T>& v, const Mask& keep, std::size_t stride = 1) {
  const std::size_t n = v.size() / stride;
  std::size_t out = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!keep[i]) continue;
    if (out != i)
      for (std::size_t k = 0; k < stride; ++k) v[stride * out + k] = v[stride * i + k];
    ++out;
  }
  v.resize(stride * out);
  return out;
}

}  // namespace vigs::mapping
