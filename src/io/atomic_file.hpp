#pragma once
// Atomic file replacement: write to "<path>.tmp.<pid>", fsync, then rename over <path>.
// A crash or error mid-write leaves the previous file (if any) untouched.
#include <cstdio>
#include <functional>
#include <string>

namespace vigs::io {

/// Calls `write(FILE*)` on a temporary file next to `path`; on success flushes, fsyncs and
/// renames it into place. Throws std::runtime_error naming `path` on any failure (the
/// temporary file is removed).
void write_file_atomically(const std::string& path, const std::function<void(std::FILE*)>& write);

}  // namespace vigs::io
