#pragma once
// Image files for tools and tests: PNG (8/16-bit), JPEG and float TIFF in, PNG out.
// Every failure is an ImageIoError naming the file and what is wrong with it; writes go to a
// temporary file that is renamed into place, so a failed write never leaves a partial file.
#include <stdexcept>
#include <string>

#include "core/types/image.hpp"

namespace vigs::io {

class ImageIoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// 8-bit colour or gray image from PNG or JPEG (chosen by content, not extension).
/// Gray stays 1 channel, RGB 3; RGBA and gray+alpha drop alpha; 16-bit PNG is scaled to 8 bits.
ImageU8 read_image_u8(const std::string& path);

/// The same, converted to 3-channel RGB.
ImageU8 read_rgb(const std::string& path);

/// Single-channel 16-bit PNG (e.g. depth in millimetres).
ImageU16 read_png_u16(const std::string& path);

/// Single-channel 32-bit float TIFF (e.g. depth in metres).
ImageF32 read_tiff_f32(const std::string& path);

/// Depth in metres from a 16-bit PNG (times `depth_scale_m`) or a float TIFF (as stored).
/// Invalid depth (0, NaN, negative) becomes 0.
ImageF32 read_depth_m(const std::string& path, double depth_scale_m);

/// 8-bit PNG with 1 (gray), 3 (RGB) or 4 (RGBA) channels, written atomically.
void write_png(const std::string& path, const ImageU8& image);

/// 16-bit single-channel PNG, written atomically.
void write_png_u16(const std::string& path, const ImageU16& image);

}  // namespace vigs::io
