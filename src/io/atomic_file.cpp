#include "io/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace vigs::io {

AtomicFile::AtomicFile(std::string path)
    : path_(std::move(path)), tmp_(path_ + ".tmp." + std::to_string(::getpid())) {
  file_ = std::fopen(tmp_.c_str(), "wb");
  if (!file_) {
    throw std::runtime_error(path_ + ": cannot create temporary file " + tmp_ + ": " +
                             std::strerror(errno));
  }
}

AtomicFile::~AtomicFile() {
  if (file_ != nullptr) {
    std::fclose(file_);
    std::remove(tmp_.c_str());
  }
}

void AtomicFile::commit() {
  if (file_ == nullptr) throw std::runtime_error(path_ + ": committed twice");
  std::FILE* f = file_;
  file_ = nullptr;
  if (std::fflush(f) != 0 || ::fsync(::fileno(f)) != 0) {
    const int err = errno;
    std::fclose(f);
    std::remove(tmp_.c_str());
    throw std::runtime_error(path_ + ": write failed: " + std::strerror(err));
  }
  if (std::fclose(f) != 0) {
    const int err = errno;
    std::remove(tmp_.c_str());
    throw std::runtime_error(path_ + ": close failed: " + std::strerror(err));
  }
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const int err = errno;
    std::remove(tmp_.c_str());
    throw std::runtime_error(path_ + ": rename from " + tmp_ + " failed: " + std::strerror(err));
  }
}

void write_file_atomically(const std::string& path, const std::function<void(std::FILE*)>& write) {
  AtomicFile f(path);
  write(f.file());
  f.commit();
}

}  // namespace vigs::io
