// V4l2Capture: one V4L2 capture node in mmap streaming mode, through the V4l2DeviceOps seam.
//
// open(): VIDIOC_QUERYCAP (video capture + streaming), VIDIOC_S_FMT (the configured size and
// fourcc; a node that answers with another one is refused, both named), VIDIOC_S_PARM (frame
// rate, best effort), VIDIOC_REQBUFS (mmap, `buffers`), VIDIOC_QUERYBUF + mmap of each,
// VIDIOC_QBUF of all, VIDIOC_STREAMON. Throws V4l2Error naming the node and the step (errno text);
// nothing stays open after a throw. open() allocates (the converter, error text): start-up or
// recovery path only.
// dequeue(): one non-blocking VIDIOC_DQBUF. Kernel semantics mapped to outcomes: EAGAIN (nothing
// ready), ENODEV / ENXIO / EIO-after-unplug (device gone), a buffer
// flagged V4L2_BUF_FLAG_ERROR (corrupt: counted and requeued at once), a jump in the buffer
// sequence numbers (frames the kernel dropped for want of a queued buffer: counted). Stamps:
// the kernel's timestamp when the buffer says V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC (it is then
// CLOCK_MONOTONIC already); otherwise the host time of the dequeue, counted in host_stamped.
// A dequeued buffer belongs to the caller until requeue(index).
// Real-time: dequeue/requeue only issue ioctls on preallocated structs; no allocation or lock.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "drivers/v4l2/v4l2_converter.hpp"
#include "drivers/v4l2/v4l2_device_ops.hpp"
#include "drivers/v4l2/v4l2_pixel_format.hpp"
#include "rt/counters.hpp"

namespace vigs::drivers {

class V4l2Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct V4l2CaptureSettings {
  std::string device;  ///< capture node, e.g. /dev/video0 or /dev/v4l/by-id/...
  V4l2PixelFormat format = V4l2PixelFormat::kYuyv;
  std::uint32_t width_px = 640;
  std::uint32_t height_px = 480;
  double rate_hz = 30.0;
  std::uint32_t buffers = 4;  ///< mmap buffers requested (the kernel may grant more)
};

struct V4l2Buffer {
  const std::uint8_t* data = nullptr;
  std::size_t bytes_used = 0;
  std::int64_t t_ns = 0;       ///< CLOCK_MONOTONIC capture time
  std::uint32_t sequence = 0;  ///< the kernel's frame counter
  std::uint32_t index = 0;     ///< buffer index, for requeue()
};

struct V4l2CaptureCounters {
  std::uint64_t frames = 0;          // buffers dequeued with data
  std::uint64_t corrupt = 0;         // buffers flagged V4L2_BUF_FLAG_ERROR (requeued, not used)
  std::uint64_t kernel_dropped = 0;  // frames missing from the sequence numbers
  std::uint64_t host_stamped = 0;    // buffers without a monotonic kernel timestamp
};

class V4l2Capture {
 public:
  enum class Dequeue : std::uint8_t { kFrame, kAgain, kCorrupt, kGone, kError };

  V4l2Capture(V4l2DeviceOps& ops, V4l2CaptureSettings settings);
  ~V4l2Capture();
  V4l2Capture(const V4l2Capture&) = delete;
  V4l2Capture& operator=(const V4l2Capture&) = delete;

  void open();
  /// STREAMOFF, munmap, REQBUFS 0, close. Safe on a vanished device. Idempotent.
  void close() noexcept;
  [[nodiscard]] bool is_open() const noexcept { return fd_ >= 0; }
  [[nodiscard]] int fd() const noexcept { return fd_; }

  Dequeue dequeue(V4l2Buffer& out) noexcept;
  /// Gives buffer `index` back to the kernel. False on failure (errno kept).
  bool requeue(std::uint32_t index) noexcept;

  [[nodiscard]] const V4l2CaptureSettings& settings() const noexcept { return settings_; }
  [[nodiscard]] std::uint32_t bytes_per_line() const noexcept { return bytes_per_line_; }
  [[nodiscard]] std::size_t buffer_count() const noexcept { return maps_.size(); }
  /// The colour converter of the open node (YUYV, MJPEG, GREY), or nullptr (Z16).
  [[nodiscard]] V4l2Converter* converter() noexcept { return converter_.get(); }
  [[nodiscard]] V4l2CaptureCounters counters() const noexcept;
  void reset_counters() noexcept;

 private:
  struct Map {
    void* addr = nullptr;
    std::size_t length = 0;
  };
  [[noreturn]] void fail(const std::string& step, int err);

  V4l2DeviceOps& ops_;
  V4l2CaptureSettings settings_;
  int fd_ = -1;
  bool streaming_ = false;
  std::uint32_t bytes_per_line_ = 0;
  std::vector<Map> maps_;
  std::unique_ptr<V4l2Converter> converter_;
  bool have_sequence_ = false;
  std::uint32_t last_sequence_ = 0;
  rt::SingleWriterCounter frames_, corrupt_, kernel_dropped_, host_stamped_;
};

}  // namespace vigs::drivers
