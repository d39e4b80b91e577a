#pragma once
// Pinhole intrinsics from a small camera file, for tools such as `vigs align`. Accepted:
//  - VIGS form (YAML): fx, fy, cx, cy (px), width, height (px);
//  - Kimera-VIO form (e.g. uHumans2 sensorLeft.yaml): intrinsics: [fx, fy, cx, cy],
//    resolution: [width, height] (an OpenCV "%YAML:1.0" first line is tolerated);
//  - Open3D PinholeCameraIntrinsic JSON (camera_primesense.json): width, height,
//    intrinsic_matrix (9 values, column-major 3x3).
#include <stdexcept>
#include <string>

#include "core/types/pinhole_camera.hpp"

namespace vigs::tracking {

class CameraFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws CameraFileError naming the file and the missing or bad key.
PinholeCamera load_camera_file(const std::string& path);

/// The same from text; `name` is used in messages.
PinholeCamera parse_camera_text(const std::string& text, const std::string& name);

}  // namespace vigs::tracking
