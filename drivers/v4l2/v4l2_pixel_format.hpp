// The capture formats the V4L2 driver takes, by fourcc, and what each becomes in the FramePool.
//   YUYV  (V4L2_PIX_FMT_YUYV)  colour, 4:2:2        -> rgb8 through libv4lconvert
//   MJPG  (V4L2_PIX_FMT_MJPEG) colour, Motion JPEG  -> rgb8 through libv4lconvert (libjpeg)
//   GREY  (V4L2_PIX_FMT_GREY)  8-bit mono           -> mono8 copy (1-channel pool) or rgb8
//                                                      through libv4lconvert (3-channel pool)
//   Z16   (V4L2_PIX_FMT_Z16)   16-bit depth          -> the depth plane (raw device units;
//                                                      RealSense-class UVC cameras: 1 mm)
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace vigs::drivers {

enum class V4l2PixelFormat : std::uint8_t { kYuyv, kMjpeg, kGrey, kZ16 };

/// The kernel's fourcc code (linux/videodev2.h).
[[nodiscard]] std::uint32_t fourcc(V4l2PixelFormat f) noexcept;
/// "YUYV", "MJPG", "GREY", "Z16 " (the fourcc's four characters).
[[nodiscard]] std::string_view fourcc_name(V4l2PixelFormat f) noexcept;
/// Parses a config name: "YUYV", "MJPG"/"MJPEG", "GREY", "Z16" (case-insensitive).
[[nodiscard]] std::optional<V4l2PixelFormat> parse_pixel_format(std::string_view name) noexcept;
/// The four characters of any fourcc, for messages ("BA81").
[[nodiscard]] std::string fourcc_text(std::uint32_t code);
/// Bytes per pixel of an uncompressed format in the kernel buffer (MJPEG: 0, variable).
[[nodiscard]] std::uint32_t raw_bytes_per_pixel(V4l2PixelFormat f) noexcept;
[[nodiscard]] constexpr bool is_depth(V4l2PixelFormat f) noexcept {
  return f == V4l2PixelFormat::kZ16;
}

}  // namespace vigs::drivers
