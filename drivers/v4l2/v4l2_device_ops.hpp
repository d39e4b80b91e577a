// V4l2DeviceOps: the thin seam between the V4L2 driver and the kernel, at the open / ioctl / mmap
// / poll boundary. Every call has the kernel's contract: -1 (MAP_FAILED for mmap) with errno
// set on failure (EAGAIN from a non-blocking VIDIOC_DQBUF with nothing ready, ENODEV once the
// device is unplugged, EINVAL for an unsupported request), ioctl arguments are the kernel's
// structs (linux/videodev2.h).
//
// libv4l2_device_ops() is the real one, on Debian's libv4l2: open(2) with O_NONBLOCK, then
// v4l2_fd_open(fd, V4L2_DISABLE_CONVERSION) (libv4l2 passes raw formats through; conversion is
// done explicitly by V4l2Converter on libv4lconvert), v4l2_ioctl (retried on EINTR), v4l2_mmap,
// v4l2_munmap, v4l2_close, and poll(2). This kernel has no video devices, so tests put a fake
// with the same semantics behind this interface (tests/drivers/fake_v4l2_device.hpp).
#pragma once

#include <poll.h>
#include <sys/types.h>

#include <cstddef>

namespace vigs::drivers {

class V4l2DeviceOps {
 public:
  virtual ~V4l2DeviceOps() = default;
  /// Opens a capture node read-write, non-blocking. Returns an fd or -1 (errno).
  virtual int open(const char* path) = 0;
  virtual int close(int fd) = 0;
  /// One V4L2 ioctl; -1 with errno on failure.
  virtual int ioctl(int fd, unsigned long request, void* arg) = 0;
  /// mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, offset); MAP_FAILED on error.
  virtual void* mmap(std::size_t length, int fd, off_t offset) = 0;
  virtual int munmap(void* addr, std::size_t length) = 0;
  /// poll(2) on capture fds (POLLIN: a buffer is ready to dequeue; POLLERR: device gone or not
  /// streaming).
  virtual int poll(pollfd* fds, nfds_t count, int timeout_ms) = 0;
};

/// The real device operations (libv4l2). One process-wide instance; thread-safe.
[[nodiscard]] V4l2DeviceOps& libv4l2_device_ops();

}  // namespace vigs::drivers
