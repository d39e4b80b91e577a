#pragma once
// Numbers read from a file are checked as finite where they enter: a NaN or infinity in a
// file is an IoError naming the file, the record and the field, so it never reaches an
// estimate or an output. (Sensor samples on live paths are dropped and counted instead; see
// drivers/serial_imu.)
#include <cmath>
#include <string>

#include "io/io_error.hpp"

namespace vigs::io {

/// `value` if finite, else IoError "where: field is not finite (nan)".
inline double require_finite(const std::string& where, const char* field, double value) {
  if (!std::isfinite(value)) {
    throw IoError(where + ": " + field + " is not finite (" +
                  (std::isnan(value) ? "nan"
                   : value > 0       ? "inf"
                                     : "-inf") +
                  ")");
  }
  return value;
}

/// All of `n` values finite; the first that is not is named as field[i].
inline void require_all_finite(const std::string& where, const char* field, const double* v,
                               std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) {
      require_finite(where, (std::string(field) + "[" + std::to_string(i) + "]").c_str(), v[i]);
    }
  }
}

}  // namespace vigs::io
