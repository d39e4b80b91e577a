#pragma once
// RgbdView: one registered RGB-D frame as the tracker and the keyframe builder take it, without
// owning its pixels. The live path (a FramePool slot, pipeline/pool_frame_view.hpp) and the
// recording reader (io/recording/recorded_frames.hpp) both produce it, so everything after the
// source is the same code for both.
//
// Depth is either raw 16-bit units with a scale (16UC1; OpenNI2 and REP 118 recordings: mm) or
// float metres (32FC1). Raw depth is turned into metres pixel by pixel, in single precision, as
// `float(raw) * depth_scale_m`: the same float a reader that converts 16UC1 to a float image
// gets, so both paths give bit-identical points. No float depth image is made per frame.
// Colour is rgb8 or mono8 (mono8 reads as grey RGB). Either may be absent: no depth reads as
// 0 (no measurement) everywhere, no colour as black.
//
// The view is valid while its producer keeps the pixels (the pool slot is held, or the reader's
// callback has not returned). Rows are `row_stride` elements apart (>= width * channels).
// Time: `t_ns` is the frame's integer stamp (CLOCK_MONOTONIC live, the header stamp of a
// recording) and stays an integer down to the pose.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "core/types/image.hpp"

namespace vigs {

enum class DepthEncoding : std::uint8_t {
  none,        ///< no depth image: every pixel has no measurement
  u16_scaled,  ///< uint16 raw units, metres = float(raw) * depth_scale_m; 0 = no measurement
  f32_metres,  ///< float metres; 0, negative, NaN or infinite = no measurement
};

enum class ColourEncoding : std::uint8_t {
  none,   ///< no colour image: colours read as black
  rgb8,   ///< 3 bytes per pixel, R G B
  mono8,  ///< 1 byte per pixel, read as (g, g, g)
};

struct RgbdView {
  std::int64_t t_ns = 0;  ///< capture stamp
  int width_px = 0;
  int height_px = 0;

  DepthEncoding depth_encoding = DepthEncoding::none;
  const std::uint16_t* depth_u16 = nullptr;  ///< u16_scaled
  const float* depth_f32_m = nullptr;        ///< f32_metres
  std::size_t depth_row_stride = 0;          ///< elements between row starts
  float depth_scale_m = 0.001f;              ///< metres per raw unit (u16_scaled)

  ColourEncoding colour_encoding = ColourEncoding::none;
  const std::uint8_t* colour = nullptr;
  std::size_t colour_row_stride = 0;  ///< bytes between row starts

  [[nodiscard]] bool has_depth() const { return depth_encoding != DepthEncoding::none; }
  [[nodiscard]] bool has_colour() const { return colour_encoding != ColourEncoding::none; }

  /// Calls `fn(depth_at)` once, with `depth_at(u, v)` returning the pixel's depth in metres as
  /// a float (0 where there is no depth image); the dispatch on the encoding happens here, not
  /// per pixel.
  template <class Fn>
  decltype(auto) with_depth_m(Fn&& fn) const {
    switch (depth_encoding) {
      case DepthEncoding::u16_scaled: {
        const std::uint16_t* d = depth_u16;
        const std::size_t stride = depth_row_stride;
        const float scale = depth_scale_m;
        return fn([d, stride, scale](int u, int v) {
          return static_cast<float>(
                     d[static_cast<std::size_t>(v) * stride + static_cast<std::size_t>(u)]) *
                 scale;
        });
      }
      case DepthEncoding::f32_metres: {
        const float* d = depth_f32_m;
        const std::size_t stride = depth_row_stride;
        return fn([d, stride](int u, int v) {
          return d[static_cast<std::size_t>(v) * stride + static_cast<std::size_t>(u)];
        });
      }
      case DepthEncoding::none:
        break;
    }
    return fn([](int, int) { return 0.0f; });
  }

  /// Colour of pixel (u, v) as R, G, B.
  [[nodiscard]] std::array<std::uint8_t, 3> rgb_at(int u, int v) const {
    const std::size_t row = static_cast<std::size_t>(v) * colour_row_stride;
    switch (colour_encoding) {
      case ColourEncoding::rgb8: {
        const std::uint8_t* p = colour + row + 3 * static_cast<std::size_t>(u);
        return {p[0], p[1], p[2]};
      }
      case ColourEncoding::mono8: {
        const std::uint8_t g = colour[row + static_cast<std::size_t>(u)];
        return {g, g, g};
      }
      case ColourEncoding::none:
        break;
    }
    return {0, 0, 0};
  }
};

namespace detail {
inline void check_colour_matches(int width, int height, const ImageU8& rgb) {
  if (rgb.empty()) return;
  if (rgb.channels != 1 && rgb.channels != 3)
    throw std::invalid_argument("colour image has " + std::to_string(rgb.channels) +
                                " channels (1 = mono8 or 3 = rgb8 expected)");
  if (width != 0 && (rgb.width != width || rgb.height != height))
    throw std::invalid_argument("colour image is " + std::to_string(rgb.width) + "x" +
                                std::to_string(rgb.height) + " but depth is " +
                                std::to_string(width) + "x" + std::to_string(height));
}
}  // namespace detail

/// A view of owned images (tools and tests). `depth_m`: 1 channel, metres, or empty for none;
/// `rgb`: 3 channels (rgb8), 1 channel (mono8) or empty, the size of the depth image. Throws
/// std::invalid_argument on any other channel count or a size mismatch.
inline RgbdView rgbd_view(std::int64_t t_ns, const ImageF32& depth_m, const ImageU8& rgb) {
  if (!depth_m.empty() && depth_m.channels != 1)
    throw std::invalid_argument("depth image must have 1 channel, has " +
                                std::to_string(depth_m.channels));
  detail::check_colour_matches(depth_m.width, depth_m.height, rgb);
  RgbdView f;
  f.t_ns = t_ns;
  f.width_px = depth_m.empty() ? rgb.width : depth_m.width;
  f.height_px = depth_m.empty() ? rgb.height : depth_m.height;
  if (!depth_m.empty()) {
    f.depth_encoding = DepthEncoding::f32_metres;
    f.depth_f32_m = depth_m.data.data();
    f.depth_row_stride = static_cast<std::size_t>(depth_m.width);
  }
  if (!rgb.empty()) {
    f.colour_encoding = rgb.channels == 1 ? ColourEncoding::mono8 : ColourEncoding::rgb8;
    f.colour = rgb.data.data();
    f.colour_row_stride = static_cast<std::size_t>(rgb.width) * rgb.channels;
  }
  return f;
}

/// The same with raw 16-bit depth (`depth_raw`: 1 channel) and its scale in metres per unit.
inline RgbdView rgbd_view(std::int64_t t_ns, const ImageU16& depth_raw, float depth_scale_m,
                          const ImageU8& rgb) {
  if (!depth_raw.empty() && depth_raw.channels != 1)
    throw std::invalid_argument("depth image must have 1 channel, has " +
                                std::to_string(depth_raw.channels));
  detail::check_colour_matches(depth_raw.width, depth_raw.height, rgb);
  RgbdView f = rgbd_view(t_ns, ImageF32{}, rgb);
  if (!depth_raw.empty()) {
    f.width_px = depth_raw.width;
    f.height_px = depth_raw.height;
    f.depth_encoding = DepthEncoding::u16_scaled;
    f.depth_u16 = depth_raw.data.data();
    f.depth_row_stride = static_cast<std::size_t>(depth_raw.width);
    f.depth_scale_m = depth_scale_m;
  }
  return f;
}

/// Copies the colour into `rgb` as 3-channel RGB (mono8 as grey; none: an empty image).
/// Reuses rgb's capacity.
inline void copy_rgb8(const RgbdView& f, ImageU8& rgb) {
  if (!f.has_colour()) {
    rgb = ImageU8();
    return;
  }
  rgb.width = f.width_px;
  rgb.height = f.height_px;
  rgb.channels = 3;
  rgb.data.resize(static_cast<std::size_t>(f.width_px) * f.height_px * 3);
  std::size_t i = 0;
  for (int v = 0; v < f.height_px; ++v)
    for (int u = 0; u < f.width_px; ++u)
      for (const std::uint8_t c : f.rgb_at(u, v)) rgb.data[i++] = c;
}

/// Copies the depth into `depth_m` in metres, with 0 wherever there is no measurement (no
/// depth image, 0, negative or non-finite). Reuses depth_m's capacity.
inline void copy_depth_m(const RgbdView& f, ImageF32& depth_m) {
  depth_m.width = f.width_px;
  depth_m.height = f.height_px;
  depth_m.channels = 1;
  depth_m.data.resize(static_cast<std::size_t>(f.width_px) * f.height_px);
  f.with_depth_m([&](auto depth_at) {
    std::size_t i = 0;
    for (int v = 0; v < f.height_px; ++v)
      for (int u = 0; u < f.width_px; ++u) {
        const float z = depth_at(u, v);
        depth_m.data[i++] = std::isfinite(z) && z > 0 ? z : 0.0f;
      }
  });
}

}  // namespace vigs
