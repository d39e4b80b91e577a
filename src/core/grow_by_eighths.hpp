#pragma once
// Resizing a vector that grows a little at a time (a map that gains one keyframe's Gaussians per
// tick, and the per-Gaussian state beside it): std::vector doubles its capacity when it runs
// out, so at a random moment a quarter of the largest arrays (mean) and up to half of them is
// allocated but unused. For the mapper's per-Gaussian arrays (hundreds of MB on a 3-minute map)
// that is the largest part of the memory that is not the map. Growing by an eighth instead keeps
// the slack under 12.5 % and still re-allocates only a logarithmic number of times.
#include <cstddef>
#include <vector>

namespace vigs {

/// v.resize(n), reserving n + n / 8 first when n exceeds the capacity.
template <class T, class A>
void resize_by_eighths(std::vector<T, A>& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(n + n / 8);
  v.resize(n);
}

}  // namespace vigs
