#include "io/image_io.hpp"

#include <jpeglib.h>
#include <png.h>
#include <tiffio.h>

#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <memory>

#include "io/atomic_file.hpp"

namespace vigs::io {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

FilePtr open_or_throw(const std::string& path) {
  FilePtr f(std::fopen(path.c_str(), "rb"));
  if (!f) throw ImageIoError(path + ": cannot open: " + std::strerror(errno));
  return f;
}

enum class Format { kPng, kJpeg, kTiff, kUnknown };

Format sniff(const std::string& path) {
  auto f = open_or_throw(path);
  unsigned char magic[8] = {};
  const std::size_t n = std::fread(magic, 1, sizeof magic, f.get());
  if (n >= 8 && png_sig_cmp(magic, 0, 8) == 0) return Format::kPng;
  if (n >= 3 && magic[0] == 0xFF && magic[1] == 0xD8 && magic[2] == 0xFF) return Format::kJpeg;
  if (n >= 4 && ((magic[0] == 'I' && magic[1] == 'I' && magic[2] == 42 && magic[3] == 0) ||
                 (magic[0] == 'M' && magic[1] == 'M' && magic[2] == 0 && magic[3] == 42))) {
    return Format::kTiff;
  }
  return Format::kUnknown;
}

// ---- PNG ----------------------------------------------------------------------------------

struct PngError {
  std::jmp_buf jump;
  char message[256] = "unknown libpng error";
};

void png_error_fn(png_structp png, png_const_charp msg) {
  auto* err = static_cast<PngError*>(png_get_error_ptr(png));
  std::snprintf(err->message, sizeof err->message, "%s", msg);
  std::longjmp(err->jump, 1);
}
void png_warning_fn(png_structp, png_const_charp) {}

/// Decoded PNG: 8- or 16-bit samples (16-bit in native byte order), alpha kept.
struct RawPng {
  int width = 0, height = 0, channels = 0, bit_depth = 0;
  std::vector<std::uint8_t> bytes;
};

RawPng decode_png(const std::string& path) {
  auto f = open_or_throw(path);
  PngError err;
  png_structp png =
      png_create_read_struct(PNG_LIBPNG_VER_STRING, &err, png_error_fn, png_warning_fn);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info) throw ImageIoError(path + ": libpng initialisation failed");
  RawPng raw;
  std::vector<png_bytep> rows;
  if (setjmp(err.jump)) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw ImageIoError(path + ": invalid PNG: " + err.message);
  }
  png_init_io(png, f.get());
  png_set_user_limits(png, 1 << 15, 1 << 15);
  png_read_info(png, info);
  png_set_expand(png);  // palette -> RGB, gray < 8 bits -> 8 bits, tRNS -> alpha
  if (png_get_bit_depth(png, info) == 16) png_set_swap(png);  // to little-endian
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  raw.width = static_cast<int>(png_get_image_width(png, info));
  raw.height = static_cast<int>(png_get_image_height(png, info));
  raw.channels = png_get_channels(png, info);
  raw.bit_depth = png_get_bit_depth(png, info);
  const std::size_t row_bytes = png_get_rowbytes(png, info);
  raw.bytes.resize(row_bytes * raw.height);
  rows.resize(raw.height);
  for (int y = 0; y < raw.height; ++y) rows[y] = raw.bytes.data() + row_bytes * y;
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return raw;
}

ImageU8 png_to_u8(const RawPng& raw) {
  const int out_channels =
      (raw.channels == 2 || raw.channels == 4) ? raw.channels - 1 : raw.channels;
  ImageU8 img(raw.width, raw.height, out_channels);
  const std::size_t pixels = static_cast<std::size_t>(raw.width) * raw.height;
  for (std::size_t p = 0; p < pixels; ++p) {
    for (int c = 0; c < out_channels; ++c) {
      const std::size_t s = p * raw.channels + c;
      if (raw.bit_depth == 16) {
        std::uint16_t v;
        std::memcpy(&v, raw.bytes.data() + 2 * s, 2);
        img.data[p * out_channels + c] = static_cast<std::uint8_t>((v + 128) / 257);
      } else {
        img.data[p * out_channels + c] = raw.bytes[s];
      }
    }
  }
  return img;
}

// ---- JPEG ---------------------------------------------------------------------------------

struct JpegError {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX] = {};
};

void jpeg_error_fn(j_common_ptr cinfo) {
  auto* err = reinterpret_cast<JpegError*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, err->message);
  std::longjmp(err->jump, 1);
}

ImageU8 decode_jpeg(const std::string& path) {
  auto f = open_or_throw(path);
  jpeg_decompress_struct cinfo;
  JpegError err;
  cinfo.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = jpeg_error_fn;
  ImageU8 img;
  if (setjmp(err.jump)) {
    jpeg_destroy_decompress(&cinfo);
    throw ImageIoError(path + ": invalid JPEG: " + err.message);
  }
  jpeg_create_decompress(&cinfo);
  jpeg_stdio_src(&cinfo, f.get());
  jpeg_read_header(&cinfo, TRUE);
  if (cinfo.jpeg_color_space != JCS_GRAYSCALE) cinfo.out_color_space = JCS_RGB;
  jpeg_start_decompress(&cinfo);
  img = ImageU8(static_cast<int>(cinfo.output_width), static_cast<int>(cinfo.output_height),
                cinfo.output_components);
  while (cinfo.output_scanline < cinfo.output_height) {
    JSAMPROW row = img.data.data() + img.index(0, static_cast<int>(cinfo.output_scanline));
    jpeg_read_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_decompress(&cinfo);
  jpeg_destroy_decompress(&cinfo);
  return img;
}

// ---- PNG writing --------------------------------------------------------------------------

void encode_png(const std::string& path, int width, int height, int channels, int bit_depth,
                const std::uint8_t* data) {
  if (width <= 0 || height <= 0) throw ImageIoError(path + ": cannot write an empty image");
  int color_type = 0;
  switch (channels) {
    case 1:
      color_type = PNG_COLOR_TYPE_GRAY;
      break;
    case 3:
      color_type = PNG_COLOR_TYPE_RGB;
      break;
    case 4:
      color_type = PNG_COLOR_TYPE_RGBA;
      break;
    default:
      throw ImageIoError(path + ": PNG needs 1, 3 or 4 channels, got " + std::to_string(channels));
  }
  try {
    write_file_atomically(path, [&](std::FILE* f) {
      PngError err;
      png_structp png =
          png_create_write_struct(PNG_LIBPNG_VER_STRING, &err, png_error_fn, png_warning_fn);
      png_infop info = png ? png_create_info_struct(png) : nullptr;
      if (!png || !info) throw ImageIoError(path + ": libpng initialisation failed");
      if (setjmp(err.jump)) {
        png_destroy_write_struct(&png, &info);
        throw ImageIoError(path + ": PNG encoding failed: " + err.message);
      }
      png_init_io(png, f);
      png_set_compression_level(png, 3);
      png_set_IHDR(png, info, width, height, bit_depth, color_type, PNG_INTERLACE_NONE,
                   PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
      png_write_info(png, info);
      if (bit_depth == 16) png_set_swap(png);  // our samples are little-endian
      const std::size_t row_bytes = static_cast<std::size_t>(width) * channels * bit_depth / 8;
      for (int y = 0; y < height; ++y) {
        png_write_row(png, const_cast<png_bytep>(data + row_bytes * y));
      }
      png_write_end(png, nullptr);
      png_destroy_write_struct(&png, &info);
    });
  } catch (const ImageIoError&) {
    throw;
  } catch (const std::exception& e) {
    throw ImageIoError(e.what());
  }
}

}  // namespace

ImageU8 read_image_u8(const std::string& path) {
  switch (sniff(path)) {
    case Format::kPng:
      return png_to_u8(decode_png(path));
    case Format::kJpeg:
      return decode_jpeg(path);
    case Format::kTiff:
      throw ImageIoError(path + ": TIFF is read only as float depth");
    case Format::kUnknown:
      break;
  }
  throw ImageIoError(path + ": not a PNG or JPEG file (unrecognised signature)");
}

ImageU8 read_rgb(const std::string& path) {
  ImageU8 img = read_image_u8(path);
  if (img.channels == 3) return img;
  ImageU8 rgb(img.width, img.height, 3);
  const std::size_t pixels = static_cast<std::size_t>(img.width) * img.height;
  for (std::size_t p = 0; p < pixels; ++p) {
    for (int c = 0; c < 3; ++c) rgb.data[p * 3 + c] = img.data[p * img.channels];
  }
  return rgb;
}

ImageU16 read_png_u16(const std::string& path) {
  if (sniff(path) != Format::kPng) throw ImageIoError(path + ": not a PNG file");
  const RawPng raw = decode_png(path);
  if (raw.channels != 1 || raw.bit_depth != 16) {
    throw ImageIoError(path + ": expected a single-channel 16-bit PNG, got " +
                       std::to_string(raw.channels) + " channel(s) of " +
                       std::to_string(raw.bit_depth) + " bits");
  }
  ImageU16 img(raw.width, raw.height, 1);
  std::memcpy(img.data.data(), raw.bytes.data(), img.data.size() * 2);
  return img;
}

namespace {
thread_local std::string g_tiff_error;
void tiff_error_fn(const char* module, const char* fmt, va_list args) {
  char buf[512];
  std::vsnprintf(buf, sizeof buf, fmt, args);
  g_tiff_error = std::string(module ? module : "libtiff") + ": " + buf;
}
void tiff_warning_fn(const char*, const char*, va_list) {}
}  // namespace

ImageF32 read_tiff_f32(const std::string& path) {
  if (sniff(path) != Format::kTiff) throw ImageIoError(path + ": not a TIFF file");
  TIFFSetErrorHandler(tiff_error_fn);
  TIFFSetWarningHandler(tiff_warning_fn);
  g_tiff_error.clear();
  std::unique_ptr<TIFF, void (*)(TIFF*)> tif(TIFFOpen(path.c_str(), "r"), TIFFClose);
  if (!tif) throw ImageIoError(path + ": invalid TIFF: " + g_tiff_error);
  std::uint32_t width = 0, height = 0;
  std::uint16_t bits = 0, samples = 1, format = SAMPLEFORMAT_UINT;
  TIFFGetField(tif.get(), TIFFTAG_IMAGEWIDTH, &width);
  TIFFGetField(tif.get(), TIFFTAG_IMAGELENGTH, &height);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_SAMPLESPERPIXEL, &samples);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_SAMPLEFORMAT, &format);
  if (bits != 32 || samples != 1 || format != SAMPLEFORMAT_IEEEFP) {
    throw ImageIoError(path + ": expected a single-channel 32-bit float TIFF, got " +
                       std::to_string(samples) + " sample(s) of " + std::to_string(bits) +
                       " bits, sample format " + std::to_string(format));
  }
  if (TIFFIsTiled(tif.get())) throw ImageIoError(path + ": tiled TIFF is not supported");
  if (width == 0 || height == 0 || width > (1u << 15) || height > (1u << 15)) {
    throw ImageIoError(path + ": implausible TIFF size " + std::to_string(width) + "x" +
                       std::to_string(height));
  }
  if (static_cast<std::size_t>(TIFFScanlineSize(tif.get())) != width * sizeof(float)) {
    throw ImageIoError(path + ": unexpected TIFF scanline size");
  }
  ImageF32 img(static_cast<int>(width), static_cast<int>(height), 1);
  for (std::uint32_t y = 0; y < height; ++y) {
    if (TIFFReadScanline(tif.get(), img.data.data() + img.index(0, static_cast<int>(y)), y) < 0) {
      throw ImageIoError(path + ": TIFF read failed at row " + std::to_string(y) + ": " +
                         g_tiff_error);
    }
  }
  return img;
}

ImageF32 read_depth_m(const std::string& path, double depth_scale_m) {
  ImageF32 depth;
  if (sniff(path) == Format::kTiff) {
    depth = read_tiff_f32(path);
  } else {
    const ImageU16 raw = read_png_u16(path);
    depth = ImageF32(raw.width, raw.height, 1);
    for (std::size_t i = 0; i < raw.data.size(); ++i) {
      depth.data[i] = static_cast<float>(raw.data[i] * depth_scale_m);
    }
  }
  for (float& d : depth.data) {
    if (!(d > 0.0f) || !std::isfinite(d)) d = 0.0f;
  }
  return depth;
}

void write_png(const std::string& path, const ImageU8& image) {
  if (image.data.size() != static_cast<std::size_t>(image.width) * image.height * image.channels) {
    throw ImageIoError(path + ": image buffer does not match its size");
  }
  encode_png(path, image.width, image.height, image.channels, 8, image.data.data());
}

void write_png_u16(const std::string& path, const ImageU16& image) {
  if (image.channels != 1 ||
      image.data.size() != static_cast<std::size_t>(image.width) * image.height) {
    throw ImageIoError(path + ": 16-bit PNG needs a single-channel image of matching size");
  }
  encode_png(path, image.width, image.height, 1, 16,
             reinterpret_cast<const std::uint8_t*>(image.data.data()));
}

}  // namespace vigs::io
