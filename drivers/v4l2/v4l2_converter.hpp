// V4l2Converter: a captured colour buffer (YUYV, MJPEG, GREY) to rgb8 through Debian's
// libv4lconvert, created on the open device through the same V4l2DeviceOps seam (libv4lconvert
// asks the device for its formats and controls with its own ioctls: they go through the seam, so
// the fake device of the tests answers them as well).
//
// Real-time: libv4lconvert keeps its conversion buffers between calls, so YUYV and GREY convert
// without allocating after the first frame; MJPEG decoding goes through libjpeg, whose memory
// manager allocates per image (inside libjpeg, like OpenNI2's own allocations).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "drivers/v4l2/v4l2_device_ops.hpp"
#include "drivers/v4l2/v4l2_pixel_format.hpp"

struct v4lconvert_data;

namespace vigs::drivers {

class V4l2Converter {
 public:
  /// Throws std::runtime_error if libv4lconvert cannot be created on `fd`.
  V4l2Converter(V4l2DeviceOps& ops, int fd, V4l2PixelFormat src, std::uint32_t width_px,
                std::uint32_t height_px, std::uint32_t bytes_per_line);
  ~V4l2Converter();
  V4l2Converter(const V4l2Converter&) = delete;
  V4l2Converter& operator=(const V4l2Converter&) = delete;

  /// Converts `bytes` (bytesused of one buffer) into `rgb` (width*height*3). Returns false on a
  /// corrupt frame (libv4lconvert's error text: error()). No exception, no log.
  bool to_rgb8(std::span<const std::uint8_t> bytes, std::span<std::uint8_t> rgb) noexcept;
  [[nodiscard]] const char* error() const noexcept;

 private:
  V4l2DeviceOps& ops_;
  v4lconvert_data* data_ = nullptr;
  V4l2PixelFormat src_;
  std::uint32_t width_px_, height_px_, bytes_per_line_;
};

}  // namespace vigs::drivers
