#pragma once
#include <stdexcept>
#include <string>

namespace vigs::io {

/// A file could not be opened, written, renamed or parsed. The message names the file and,
/// where it applies, the line, field or byte offset.
class IoError : public std::runtime_error {
 public:
  explicit IoError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace vigs::io
