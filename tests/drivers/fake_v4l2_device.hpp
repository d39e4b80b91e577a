// FakeV4l2Device: V4L2 capture nodes in memory behind the driver's V4l2DeviceOps seam, with the
// kernel's semantics (linux/videodev2.h, videobuf2): QUERYCAP, ENUM_FMT, S_FMT/G_FMT/TRY_FMT
// (the node's own size and fourcc win, as a driver adjusting the request), S_PARM, REQBUFS,
// QUERYBUF, mmap by offset, QBUF/DQBUF (non-blocking: EAGAIN when nothing is done; EINVAL for a
// buffer the caller does not own or when not streaming), STREAMON/OFF (OFF returns every buffer to
// the caller), poll (POLLIN when a buffer is done, POLLERR when not streaming or unplugged), and
// unplug(): every call then fails with ENODEV, poll says POLLERR | POLLHUP, and open fails with
// ENOENT until replug().
//
// The test plays the camera: push_frame() fills the oldest queued buffer (bytesused, timestamp
// with V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC unless told otherwise, sequence, V4L2_BUF_FLAG_ERROR on
// request) and marks it done; with no buffer queued the frame is dropped as the kernel does, and
// the sequence number still advances. Thread-safe (one mutex; test code, not real-time).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "drivers/v4l2/v4l2_device_ops.hpp"

namespace vigs::drivers::testing {

struct FakeNodeSpec {
  std::uint32_t pixelformat = 0;  // V4L2_PIX_FMT_*
  std::uint32_t width = 0, height = 0;
  std::uint32_t bytes_per_line = 0;  // 0: packed (MJPEG: 0)
  std::uint32_t size_image = 0;      // buffer size
  std::uint32_t max_buffers = 8;
};

struct FakeFrame {
  std::span<const std::uint8_t> bytes;
  std::int64_t t_ns = 0;            // kernel timestamp (CLOCK_MONOTONIC)
  bool monotonic_flag = true;       // V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC, else TIMESTAMP_UNKNOWN
  bool error_flag = false;          // V4L2_BUF_FLAG_ERROR
  std::uint32_t skip_sequence = 0;  // sequence numbers the "kernel" skips before this frame
};

class FakeV4l2Device final : public V4l2DeviceOps {
 public:
  void add_node(const std::string& path, const FakeNodeSpec& spec);
  /// Returns false when the frame was dropped (no queued buffer, not streaming, unplugged).
  bool push_frame(const std::string& path, const FakeFrame& frame);
  void unplug(const std::string& path);
  /// The next `count` polls report POLLIN on this node with nothing to dequeue (EAGAIN).
  void spurious_wakeups(const std::string& path, int count);
  void replug(const std::string& path);
  /// Buffers queued to the fake kernel right now (waiting for a frame).
  std::size_t queued(const std::string& path);
  bool streaming(const std::string& path);
  int opens(const std::string& path);
  /// Wakes poll() (a frame pushed, an unplug) -- called by the above.
  void notify();

  int open(const char* path) override;
  int close(int fd) override;
  int ioctl(int fd, unsigned long request, void* arg) override;
  void* mmap(std::size_t length, int fd, off_t offset) override;
  int munmap(void* addr, std::size_t length) override;
  int poll(pollfd* fds, nfds_t count, int timeout_ms) override;

 private:
  enum class BufState { kUser, kQueued, kDone };
  struct Buffer {
    std::vector<std::uint8_t> memory;
    BufState state = BufState::kUser;
    std::uint32_t bytes_used = 0, sequence = 0, flags = 0;
    std::int64_t t_ns = 0;
  };
  struct Node {
    FakeNodeSpec spec;
    bool present = true;
    bool streaming = false;
    int open_count = 0;
    int opens = 0;
    std::uint32_t sequence = 0;
    int spurious = 0;
    int generation = 0;  // bumped by replug(): fds of the old instance stay dead (ENODEV)
    std::vector<std::unique_ptr<Buffer>> buffers;
    std::vector<std::uint32_t> queued;  // FIFO of indices
    std::vector<std::uint32_t> done;
  };
  Node* node_of(int fd, bool* stale = nullptr);  // locked; stale: an fd of an unplugged instance
  int fail(int err);
  int ioctl_locked(Node& n, unsigned long request, void* arg);

  std::mutex mutex_;
  std::condition_variable cv_;
  std::map<std::string, Node> nodes_;
  struct Fd {
    std::string path;
    int generation = 0;
  };
  std::map<int, Fd> fds_;
  int next_fd_ = 1000;
};

}  // namespace vigs::drivers::testing
