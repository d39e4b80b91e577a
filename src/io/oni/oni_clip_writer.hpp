#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace vigs::io::oni {

/// Geometry and timing of an RGB-D clip. Both streams share the resolution.
struct OniClipSettings {
  std::uint32_t width = 640;   ///< px
  std::uint32_t height = 480;  ///< px
  std::uint32_t fps = 30;      ///< frames per second of both streams
  double hfov_rad = 1.0226;    ///< horizontal field of view (ASUS Xtion / PrimeSense 58 deg)
  double vfov_rad = 0.7966;    ///< vertical field of view (45.6 deg)
};

/// Writes an uncompressed RGB-D `.oni` clip that real OpenNI2 plays back
/// (`openni::Device::open(path)`, PlaybackControl, depth PIXEL_FORMAT_DEPTH_1_MM and colour
/// PIXEL_FORMAT_RGB888 streams). Frames go to a temporary file as they are added (memory stays
/// at one frame whatever the clip's length; 720x480 is 1.7 MB a frame); close() writes the
/// header again with the frame count and last time (its size does not depend on them) and
/// renames the file into place, so `path` is whole or untouched. A writer destroyed without
/// close() (an error) removes its temporary file.
class OniClipWriter {
 public:
  /// Throws IoError if the settings are invalid (zero size, fps 0).
  OniClipWriter(std::string path, OniClipSettings settings);
  ~OniClipWriter();
  OniClipWriter(const OniClipWriter&) = delete;
  OniClipWriter& operator=(const OniClipWriter&) = delete;

  /// Appends one frame: `depth_mm` has width*height values (0 = no depth), `rgb` has
  /// width*height*3 bytes (R G B per pixel, rows top to bottom). Throws IoError on bad sizes.
  void add_frame(std::span<const std::uint16_t> depth_mm, std::span<const std::uint8_t> rgb);

  /// Appends one frame with device timestamp `t_us` (microseconds, > 0, after the previous
  /// frame's): OpenNI2 plays it back at that time in real time (setSpeed(1)) and reports it as
  /// the frame's timestamp. add_frame() uses uniform_timestamp_us().
  void add_frame_at(std::uint64_t t_us, std::span<const std::uint16_t> depth_mm,
                    std::span<const std::uint8_t> rgb);

  /// Frame `index` of a clip at `fps` without recorded times: 1 ms + index / fps (never 0:
  /// OniFile skips a frame 0 at timestamp 0).
  [[nodiscard]] static constexpr std::uint64_t uniform_timestamp_us(std::size_t index,
                                                                    std::uint32_t fps) {
    return 1000 + index * 1'000'000ull / fps;
  }

  /// Writes the file. Throws IoError (naming the path) on failure. Idempotent.
  void close();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vigs::io::oni
