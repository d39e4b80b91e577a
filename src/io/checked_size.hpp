#pragma once
// Sizes that come from a file (image width/height/step, element counts, lengths), checked in
// 64-bit arithmetic against fixed caps and against the bytes the file really holds, before any
// allocation or indexing uses them. Every failure is an IoError naming the file (or record)
// and the field, e.g. "rec.mcap: /vigs/rgb message at byte 4711: width = 1431655766 is out of
// range [1, 32768]".
#include <cstdint>
#include <string>

#include "io/io_error.hpp"

namespace vigs::io {

/// Largest image side accepted from any file, px (libpng's default user limit is the same).
inline constexpr std::uint64_t kMaxImageSidePx = 1u << 15;
/// Largest image accepted from any file, bytes (4096 x 4096 x 4 x 4 = 256 MiB).
inline constexpr std::uint64_t kMaxImageBytes = 256ull << 20;

/// `value` of `field` in [lo, hi], else IoError "where: field = value is out of range [lo, hi]".
inline std::uint64_t check_range(const std::string& where, const char* field, std::uint64_t value,
                                 std::uint64_t lo, std::uint64_t hi) {
  if (value < lo || value > hi) {
    throw IoError(where + ": " + field + " = " + std::to_string(value) + " is out of range [" +
                  std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return value;
}

/// An image of width x height pixels of `bytes_per_px` bytes, stored as `height` rows of
/// `step` bytes in a buffer of `data_bytes`. Checks width and height against kMaxImageSidePx,
/// step >= width * bytes_per_px, step * height <= data_bytes and the total against
/// kMaxImageBytes, all in 64 bits. Returns the bytes one packed row needs (width * bytes_per_px).
inline std::uint64_t check_image_layout(const std::string& where, std::uint64_t width,
                                        std::uint64_t height, std::uint64_t bytes_per_px,
                                        std::uint64_t step, std::uint64_t data_bytes) {
  check_range(where, "width", width, 1, kMaxImageSidePx);
  check_range(where, "height", height, 1, kMaxImageSidePx);
  const std::uint64_t row = width * bytes_per_px;  // < 2^15 * 2^8: no overflow
  if (step < row) {
    throw IoError(where + ": step = " + std::to_string(step) + " is less than width x " +
                  std::to_string(bytes_per_px) + " bytes = " + std::to_string(row));
  }
  const std::uint64_t need = step * height;  // < 2^32 * 2^15: no overflow
  if (need > kMaxImageBytes) {
    throw IoError(where + ": step x height = " + std::to_string(need) +
                  " bytes is more than the limit of " + std::to_string(kMaxImageBytes));
  }
  if (need > data_bytes) {
    throw IoError(where + ": data holds " + std::to_string(data_bytes) +
                  " bytes but step x height = " + std::to_string(need));
  }
  return row;
}

/// `count` elements of `bytes_each` must fit in the `bytes_available` the file really holds.
/// Computed without overflow; IoError "where: field = count x bytes_each bytes, but only N
/// bytes follow" otherwise.
inline std::uint64_t check_count_fits(const std::string& where, const char* field,
                                      std::uint64_t count, std::uint64_t bytes_each,
                                      std::uint64_t bytes_available) {
  if (bytes_each != 0 && count > bytes_available / bytes_each) {
    throw IoError(where + ": " + field + " = " + std::to_string(count) + " elements of " +
                  std::to_string(bytes_each) + " bytes, but only " +
                  std::to_string(bytes_available) + " bytes follow");
  }
  return count;
}

}  // namespace vigs::io
