#pragma once
#include <stdexcept>
#include <string>
#include <vector>

namespace vigs::config {

/// One problem found in a configuration file, located precisely enough to fix it.
struct Diagnostic {
  std::string file;
  int line = 0;     ///< 1-based; 0 when unknown
  int column = 0;   ///< 1-based; 0 when unknown
  std::string key;  ///< dotted path, e.g. "imu.gyro_noise_density"
  std::string message;

  /// "FILE:LINE:COL: key 'a.b': message" (the compiler-style form editors jump to).
  [[nodiscard]] std::string to_string() const;
};

/// Thrown by the loader when a file has any diagnostics; carries all of them, not just the first.
class ConfigError : public std::runtime_error {
 public:
  explicit ConfigError(std::vector<Diagnostic> diagnostics);
  [[nodiscard]] const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }

 private:
  std::vector<Diagnostic> diagnostics_;
};

}  // namespace vigs::config
