#pragma once
// The fuzz input as a file: the readers under test take a path, so each input is written to
// one memfd (reused across runs) and opened as /proc/self/fd/N.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <string>

namespace vigs::fuzz {

/// Path of a file holding exactly `data`, or "" when the memfd cannot be written.
inline std::string as_file(const std::uint8_t* data, std::size_t size) {
  static const int fd = ::memfd_create("vigs_fuzz_input", 0);
  if (fd < 0 || ::ftruncate(fd, 0) != 0 ||
      ::pwrite(fd, data, size, 0) != static_cast<ssize_t>(size)) {
    return "";
  }
  return "/proc/self/fd/" + std::to_string(fd);
}

}  // namespace vigs::fuzz
