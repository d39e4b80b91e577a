#include "io/atomic_dir.hpp"

#include <fcntl.h>
#include <stdio.h>  // renameat2 (glibc >= 2.28)
#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>

#include "io/io_error.hpp"

namespace vigs::io {
namespace {

void fsync_dir(const std::filesystem::path& p) {
  const int fd = ::open(p.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  (void)::fsync(fd);
  ::close(fd);
}

}  // namespace

void replace_dir_atomically(const std::string& dir, const std::string& marker_file,
                            const std::function<void(const std::filesystem::path& tmp)>& fill) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path target = fs::absolute(dir, ec);
  if (ec) throw IoError(dir + ": " + ec.message());
  if (!target.has_filename()) target = target.parent_path();  // "out/" -> "out"
  const fs::path parent = target.parent_path();
  fs::create_directories(parent, ec);
  if (ec) throw IoError(parent.string() + ": cannot create directory: " + ec.message());

  const fs::file_status st = fs::symlink_status(target, ec);
  const bool exists = fs::exists(st);
  if (exists) {
    if (!fs::is_directory(st)) {
      throw IoError(dir + ": exists and is not a folder; refusing to replace it");
    }
    if (!fs::is_empty(target, ec) && !fs::exists(target / marker_file)) {
      throw IoError(dir + ": folder exists, is not empty and holds no " + marker_file +
                    ", so it is not an earlier output; refusing to replace it");
    }
  }

  std::string pattern = (parent / ("." + target.filename().string() + ".tmp-XXXXXX")).string();
  if (::mkdtemp(pattern.data()) == nullptr) {
    throw IoError(dir + ": cannot create temporary folder " + pattern + ": " +
                  std::strerror(errno));
  }
  const fs::path tmp(pattern);
  try {
    fill(tmp);
  } catch (...) {
    fs::remove_all(tmp, ec);
    throw;
  }
  fsync_dir(tmp);
  int rc = 0;
  if (exists) {
    rc = ::renameat2(AT_FDCWD, tmp.c_str(), AT_FDCWD, target.c_str(), RENAME_EXCHANGE);
  } else {
    rc = ::renameat2(AT_FDCWD, tmp.c_str(), AT_FDCWD, target.c_str(), RENAME_NOREPLACE);
  }
  if (rc != 0) {
    const int err = errno;
    fs::remove_all(tmp, ec);
    throw IoError(dir + ": cannot move the new folder " + tmp.string() +
                  " into place: " + std::strerror(err));
  }
  fsync_dir(parent);
  if (exists) fs::remove_all(tmp, ec);  // the old contents, now under the temporary name
}

}  // namespace vigs::io
