#pragma once
// Bytes held by vectors (capacity, not size): what the memory reports (Mapper::memory(),
// LocalMap::memory_bytes(), the rasterizer's caches) count. One helper so that every report
// counts the same way.
#include <cstddef>
#include <vector>

namespace vigs {

template <class T, class A>
[[nodiscard]] constexpr std::size_t capacity_bytes(const std::vector<T, A>& v) {
  return v.capacity() * sizeof(T);
}

/// The sum over several vectors.
template <class... V>
requires(sizeof...(V) > 1) [[nodiscard]] constexpr std::size_t capacity_bytes(const V&... v) {
  return (capacity_bytes(v) + ...);
}

}  // namespace vigs
