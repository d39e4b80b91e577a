#pragma once
// Atomic file replacement: write to "<path>.tmp.<pid>", fsync, then rename over <path>.
// A crash or error mid-write leaves the previous file (if any) untouched.
#include <cstdio>
#include <functional>
#include <string>

namespace vigs::io {

/// A file written in steps and put in place whole: the constructor opens the temporary file,
/// commit() flushes, fsyncs and renames it over `path`; destroyed without commit() (an error
/// on the way), the temporary file is removed and `path` is untouched. Throws
/// std::runtime_error naming `path` on any failure.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// The open temporary file (null after commit()).
  [[nodiscard]] std::FILE* file() const noexcept { return file_; }
  [[nodiscard]] const std::string& path() const noexcept { return path_; }
  void commit();

 private:
  std::string path_;
  std::string tmp_;
  std::FILE* file_ = nullptr;
};

/// Calls `write(FILE*)` on a temporary file next to `path`; on success flushes, fsyncs and
/// renames it into place. Throws std::runtime_error naming `path` on any failure (the
/// temporary file is removed).
void write_file_atomically(const std::string& path, const std::function<void(std::FILE*)>& write);

}  // namespace vigs::io
