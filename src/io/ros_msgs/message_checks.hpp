#pragma once
// Range and finiteness checks of decoded sensor messages, before any code sizes a buffer or
// divides by a field. `where` names the file, topic and byte offset of the record; every
// failure is an IoError naming it and the field.
#include <cstdint>
#include <string>

#include "io/checked_size.hpp"
#include "io/finite_check.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"

namespace vigs::io::ros_msgs {

/// Focal lengths above this are refused (a 32768 px wide image at 0.01 deg/px).
inline constexpr double kMaxFocalPx = 1e7;

/// width/height in [1, kMaxImageSidePx]; K finite; fx and fy in (0, kMaxFocalPx].
inline void check_camera_info(const std::string& where, const CameraInfo& info) {
  check_range(where, "width", info.width, 1, kMaxImageSidePx);
  check_range(where, "height", info.height, 1, kMaxImageSidePx);
  require_all_finite(where, "K", info.k.data(), info.k.size());
  for (const int i : {0, 4}) {
    if (!(info.k[i] > 0.0 && info.k[i] <= kMaxFocalPx)) {
      throw IoError(where + ": " + (i == 0 ? "fx (K[0])" : "fy (K[4])") + " = " +
                    std::to_string(info.k[i]) + " px is out of range (0, 1e7]");
    }
  }
}

/// The image's width, height, step and data size hold `bytes_per_px` pixels (64-bit checked,
/// io/checked_size.hpp); big-endian data is refused. Returns width * bytes_per_px.
inline std::uint64_t check_image(const std::string& where, const Image& img,
                                 std::uint64_t bytes_per_px) {
  if (img.is_bigendian && bytes_per_px > 1) throw IoError(where + ": is_bigendian is not 0");
  return check_image_layout(where, img.width, img.height, bytes_per_px, img.step, img.data.size());
}

}  // namespace vigs::io::ros_msgs
