#include <fcntl.h>
#include <libv4l2.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>

#include "drivers/v4l2/v4l2_device_ops.hpp"

namespace vigs::drivers {
namespace {

class Libv4l2DeviceOps final : public V4l2DeviceOps {
 public:
  int open(const char* path) override {
    const int fd = ::open(path, O_RDWR | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return -1;
    // Raw formats only: conversion is V4l2Converter's (libv4lconvert), done on the pool copy.
    if (v4l2_fd_open(fd, V4L2_DISABLE_CONVERSION) < 0) {
      const int e = errno;
      ::close(fd);
      errno = e;
      return -1;
    }
    return fd;
  }
  int close(int fd) override { return v4l2_close(fd); }
  int ioctl(int fd, unsigned long request, void* arg) override {
    int rc;
    do {
      rc = v4l2_ioctl(fd, request, arg);
    } while (rc < 0 && errno == EINTR);
    return rc;
  }
  void* mmap(std::size_t length, int fd, off_t offset) override {
    return v4l2_mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, offset);
  }
  int munmap(void* addr, std::size_t length) override { return v4l2_munmap(addr, length); }
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override {
    return ::poll(fds, count, timeout_ms);
  }
};

}  // namespace

V4l2DeviceOps& libv4l2_device_ops() {
  static Libv4l2DeviceOps ops;
  return ops;
}

}  // namespace vigs::drivers
