#include "drivers/v4l2/v4l2_capture.hpp"

#include <linux/videodev2.h>
#include <sys/mman.h>

#include <cerrno>
#include <cmath>
#include <cstring>

#include "rt/clock.hpp"

namespace vigs::drivers {

V4l2Capture::V4l2Capture(V4l2DeviceOps& ops, V4l2CaptureSettings settings)
    : ops_(ops), settings_(std::move(settings)) {
  if (settings_.width_px == 0 || settings_.height_px == 0 || settings_.buffers < 2) {
    throw std::invalid_argument("V4l2Capture: size must be > 0 and buffers >= 2");
  }
  maps_.reserve(32);
}

V4l2Capture::~V4l2Capture() {
  close();
}

void V4l2Capture::fail(const std::string& step, int err) {
  close();
  throw V4l2Error("V4L2 device '" + settings_.device + "': " + step + ": " + std::strerror(err));
}

void V4l2Capture::open() {
  close();
  fd_ = ops_.open(settings_.device.c_str());
  if (fd_ < 0) {
    const int e = errno;
    fd_ = -1;
    fail("open", e);
  }
  v4l2_capability cap{};
  if (ops_.ioctl(fd_, VIDIOC_QUERYCAP, &cap) < 0) fail("VIDIOC_QUERYCAP", errno);
  const std::uint32_t caps =
      (cap.capabilities & V4L2_CAP_DEVICE_CAPS) != 0 ? cap.device_caps : cap.capabilities;
  if ((caps & V4L2_CAP_VIDEO_CAPTURE) == 0 || (caps & V4L2_CAP_STREAMING) == 0) {
    close();
    throw V4l2Error("V4L2 device '" + settings_.device +
                    "': not a video capture node with streaming I/O");
  }

  const std::uint32_t want = fourcc(settings_.format);
  v4l2_format fmt{};
  fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  fmt.fmt.pix.width = settings_.width_px;
  fmt.fmt.pix.height = settings_.height_px;
  fmt.fmt.pix.pixelformat = want;
  fmt.fmt.pix.field = V4L2_FIELD_NONE;
  if (ops_.ioctl(fd_, VIDIOC_S_FMT, &fmt) < 0) fail("VIDIOC_S_FMT", errno);
  if (fmt.fmt.pix.pixelformat != want || fmt.fmt.pix.width != settings_.width_px ||
      fmt.fmt.pix.height != settings_.height_px) {
    const std::string got = std::to_string(fmt.fmt.pix.width) + "x" +
                            std::to_string(fmt.fmt.pix.height) + " " +
                            fourcc_text(fmt.fmt.pix.pixelformat);
    const std::string asked = std::to_string(settings_.width_px) + "x" +
                              std::to_string(settings_.height_px) + " " + fourcc_text(want);
    close();
    throw V4l2Error("V4L2 device '" + settings_.device + "': offers " + got +
                    " but the camera is configured as " + asked);
  }
  const std::uint32_t bpp = raw_bytes_per_pixel(settings_.format);
  bytes_per_line_ =
      fmt.fmt.pix.bytesperline != 0 ? fmt.fmt.pix.bytesperline : settings_.width_px * bpp;
  if (bpp != 0 && bytes_per_line_ < settings_.width_px * bpp) {
    close();
    throw V4l2Error("V4L2 device '" + settings_.device + "': bytesperline " +
                    std::to_string(bytes_per_line_) + " is shorter than a row");
  }

  v4l2_streamparm parm{};  // frame rate: best effort (many UVC nodes only take their own list)
  parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  parm.parm.capture.timeperframe.numerator = 1000;
  parm.parm.capture.timeperframe.denominator =
      static_cast<std::uint32_t>(std::lround(settings_.rate_hz * 1000.0));
  (void)ops_.ioctl(fd_, VIDIOC_S_PARM, &parm);

  v4l2_requestbuffers req{};
  req.count = settings_.buffers;
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  if (ops_.ioctl(fd_, VIDIOC_REQBUFS, &req) < 0) fail("VIDIOC_REQBUFS", errno);
  if (req.count < 2) {
    close();
    throw V4l2Error("V4L2 device '" + settings_.device + "': granted " + std::to_string(req.count) +
                    " buffers, need at least 2");
  }
  maps_.clear();
  for (std::uint32_t i = 0; i < req.count; ++i) {
    v4l2_buffer b{};
    b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    b.memory = V4L2_MEMORY_MMAP;
    b.index = i;
    if (ops_.ioctl(fd_, VIDIOC_QUERYBUF, &b) < 0) fail("VIDIOC_QUERYBUF", errno);
    void* p = ops_.mmap(b.length, fd_, static_cast<off_t>(b.m.offset));
    if (p == MAP_FAILED) fail("mmap", errno);
    maps_.push_back({p, b.length});
  }
  for (std::uint32_t i = 0; i < maps_.size(); ++i) {
    if (!requeue(i)) fail("VIDIOC_QBUF", errno);
  }
  if (settings_.format != V4l2PixelFormat::kZ16) {
    try {
      converter_ = std::make_unique<V4l2Converter>(ops_, fd_, settings_.format, settings_.width_px,
                                                   settings_.height_px, bytes_per_line_);
    } catch (const std::exception& e) {
      close();
      throw V4l2Error("V4L2 device '" + settings_.device + "': " + e.what());
    }
  }
  int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  if (ops_.ioctl(fd_, VIDIOC_STREAMON, &type) < 0) fail("VIDIOC_STREAMON", errno);
  streaming_ = true;
  have_sequence_ = false;
}

void V4l2Capture::close() noexcept {
  if (fd_ < 0) return;
  if (streaming_) {
    int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    (void)ops_.ioctl(fd_, VIDIOC_STREAMOFF, &type);  // ENODEV on a vanished node: fine
    streaming_ = false;
  }
  converter_.reset();
  for (const Map& m : maps_) (void)ops_.munmap(m.addr, m.length);
  maps_.clear();
  v4l2_requestbuffers req{};
  req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  req.memory = V4L2_MEMORY_MMAP;
  (void)ops_.ioctl(fd_, VIDIOC_REQBUFS, &req);  // count 0: free the kernel's buffers
  (void)ops_.close(fd_);
  fd_ = -1;
}

V4l2Capture::Dequeue V4l2Capture::dequeue(V4l2Buffer& out) noexcept {
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  if (ops_.ioctl(fd_, VIDIOC_DQBUF, &b) < 0) {
    switch (errno) {
      case EAGAIN:
        return Dequeue::kAgain;
      case ENODEV:
      case ENXIO:
        return Dequeue::kGone;
      default:
        return Dequeue::kError;
    }
  }
  if (have_sequence_ && b.sequence != last_sequence_ + 1) {
    kernel_dropped_.add(static_cast<std::uint32_t>(b.sequence - last_sequence_ - 1));
  }
  have_sequence_ = true;
  last_sequence_ = b.sequence;
  if ((b.flags & V4L2_BUF_FLAG_ERROR) != 0 || b.index >= maps_.size()) {
    corrupt_.add();
    if (b.index < maps_.size()) (void)requeue(b.index);
    return Dequeue::kCorrupt;
  }
  frames_.add();
  out.data = static_cast<const std::uint8_t*>(maps_[b.index].addr);
  out.bytes_used = std::min<std::size_t>(b.bytesused, maps_[b.index].length);
  out.sequence = b.sequence;
  out.index = b.index;
  if ((b.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC) {
    out.t_ns = static_cast<std::int64_t>(b.timestamp.tv_sec) * rt::kNsPerS +
               static_cast<std::int64_t>(b.timestamp.tv_usec) * rt::kNsPerUs;
  } else {
    host_stamped_.add();
    out.t_ns = rt::monotonic_ns();
  }
  return Dequeue::kFrame;
}

bool V4l2Capture::requeue(std::uint32_t index) noexcept {
  v4l2_buffer b{};
  b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  b.memory = V4L2_MEMORY_MMAP;
  b.index = index;
  return ops_.ioctl(fd_, VIDIOC_QBUF, &b) == 0;
}

V4l2CaptureCounters V4l2Capture::counters() const noexcept {
  return {.frames = frames_.get(),
          .corrupt = corrupt_.get(),
          .kernel_dropped = kernel_dropped_.get(),
          .host_stamped = host_stamped_.get()};
}

void V4l2Capture::reset_counters() noexcept {
  for (rt::SingleWriterCounter* c : {&frames_, &corrupt_, &kernel_dropped_, &host_stamped_})
    c->reset();
}

}  // namespace vigs::drivers
