#include "drivers/v4l2/v4l2_converter.hpp"

#include <libv4l-plugin.h>
#include <libv4lconvert.h>
#include <linux/videodev2.h>

#include <stdexcept>

namespace vigs::drivers {
namespace {

// libv4lconvert's device operations, forwarded to the driver's seam.
int seam_ioctl(void* priv, int fd, unsigned long request, void* arg) {
  return static_cast<V4l2DeviceOps*>(priv)->ioctl(fd, request, arg);
}
ssize_t no_read(void*, int, void*, std::size_t) {
  return -1;
}
ssize_t no_write(void*, int, const void*, std::size_t) {
  return -1;
}
const libv4l_dev_ops kSeamOps = {.init = nullptr,
                                 .close = nullptr,
                                 .ioctl = seam_ioctl,
                                 .read = no_read,
                                 .write = no_write,
                                 .reserved1 = nullptr,
                                 .reserved2 = nullptr,
                                 .reserved3 = nullptr,
                                 .reserved4 = nullptr,
                                 .reserved5 = nullptr,
                                 .reserved6 = nullptr,
                                 .reserved7 = nullptr};

v4l2_format capture_format(std::uint32_t pixelformat, std::uint32_t w, std::uint32_t h,
                           std::uint32_t bytes_per_line, std::uint32_t size_image) {
  v4l2_format f{};
  f.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  f.fmt.pix.width = w;
  f.fmt.pix.height = h;
  f.fmt.pix.pixelformat = pixelformat;
  f.fmt.pix.field = V4L2_FIELD_NONE;
  f.fmt.pix.bytesperline = bytes_per_line;
  f.fmt.pix.sizeimage = size_image;
  return f;
}

}  // namespace

V4l2Converter::V4l2Converter(V4l2DeviceOps& ops, int fd, V4l2PixelFormat src,
                             std::uint32_t width_px, std::uint32_t height_px,
                             std::uint32_t bytes_per_line)
    : ops_(ops),
      src_(src),
      width_px_(width_px),
      height_px_(height_px),
      bytes_per_line_(bytes_per_line) {
  data_ = v4lconvert_create_with_dev_ops(fd, &ops_, &kSeamOps);
  if (data_ == nullptr) throw std::runtime_error("libv4lconvert: cannot create a converter");
}

V4l2Converter::~V4l2Converter() {
  if (data_ != nullptr) v4lconvert_destroy(data_);
}

bool V4l2Converter::to_rgb8(std::span<const std::uint8_t> bytes,
                            std::span<std::uint8_t> rgb) noexcept {
  const v4l2_format src = capture_format(fourcc(src_), width_px_, height_px_, bytes_per_line_,
                                         static_cast<std::uint32_t>(bytes.size()));
  const v4l2_format dst = capture_format(V4L2_PIX_FMT_RGB24, width_px_, height_px_, width_px_ * 3,
                                         width_px_ * height_px_ * 3);
  if (rgb.size() < std::size_t{width_px_} * height_px_ * 3) return false;
  // libv4lconvert takes a non-const source pointer but does not write to it.
  const int n =
      v4lconvert_convert(data_, &src, &dst, const_cast<std::uint8_t*>(bytes.data()),
                         static_cast<int>(bytes.size()), rgb.data(), static_cast<int>(rgb.size()));
  return n == static_cast<int>(std::size_t{width_px_} * height_px_ * 3);
}

const char* V4l2Converter::error() const noexcept {
  return v4lconvert_get_error_message(data_);
}

}  // namespace vigs::drivers
