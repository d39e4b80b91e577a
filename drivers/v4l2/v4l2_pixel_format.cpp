#include "drivers/v4l2/v4l2_pixel_format.hpp"

#include <linux/videodev2.h>

#include <algorithm>
#include <cctype>

namespace vigs::drivers {

std::uint32_t fourcc(V4l2PixelFormat f) noexcept {
  switch (f) {
    case V4l2PixelFormat::kYuyv:
      return V4L2_PIX_FMT_YUYV;
    case V4l2PixelFormat::kMjpeg:
      return V4L2_PIX_FMT_MJPEG;
    case V4l2PixelFormat::kGrey:
      return V4L2_PIX_FMT_GREY;
    case V4l2PixelFormat::kZ16:
      return V4L2_PIX_FMT_Z16;
  }
  return 0;
}

std::string_view fourcc_name(V4l2PixelFormat f) noexcept {
  switch (f) {
    case V4l2PixelFormat::kYuyv:
      return "YUYV";
    case V4l2PixelFormat::kMjpeg:
      return "MJPG";
    case V4l2PixelFormat::kGrey:
      return "GREY";
    case V4l2PixelFormat::kZ16:
      return "Z16 ";
  }
  return "?";
}

std::optional<V4l2PixelFormat> parse_pixel_format(std::string_view name) noexcept {
  std::string up(name.substr(0, std::min<std::size_t>(name.size(), 8)));
  if (up.size() != name.size()) return std::nullopt;
  std::transform(up.begin(), up.end(), up.begin(),
                 [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  if (up == "YUYV") return V4l2PixelFormat::kYuyv;
  if (up == "MJPG" || up == "MJPEG") return V4l2PixelFormat::kMjpeg;
  if (up == "GREY" || up == "GRAY") return V4l2PixelFormat::kGrey;
  if (up == "Z16") return V4l2PixelFormat::kZ16;
  return std::nullopt;
}

std::string fourcc_text(std::uint32_t code) {
  std::string s(4, ' ');
  for (int i = 0; i < 4; ++i) {
    const auto c = static_cast<char>((code >> (8 * i)) & 0xFF);
    s[static_cast<std::size_t>(i)] = std::isprint(static_cast<unsigned char>(c)) ? c : '?';
  }
  return s;
}

std::uint32_t raw_bytes_per_pixel(V4l2PixelFormat f) noexcept {
  switch (f) {
    case V4l2PixelFormat::kYuyv:
    case V4l2PixelFormat::kZ16:
      return 2;
    case V4l2PixelFormat::kGrey:
      return 1;
    case V4l2PixelFormat::kMjpeg:
      return 0;
  }
  return 0;
}

}  // namespace vigs::drivers
