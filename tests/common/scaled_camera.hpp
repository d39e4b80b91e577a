#pragma once
// The default camera (uHumans2's 720x480, 90 deg horizontal field of view) at a fraction of its
// resolution with the same field of view: the tests' simulated sequences at a fraction of the
// cost.
#include "core/config/camera_settings.hpp"

namespace vigs::test {

/// `camera`'s image size and intrinsics become the default camera's divided by `divisor`.
inline void use_default_camera_divided(config::CameraSettings& camera, int divisor) {
  const config::CameraSettings d;
  camera.width_px = d.width_px / divisor;
  camera.height_px = d.height_px / divisor;
  camera.fx_px = d.fx_px / divisor;
  camera.fy_px = d.fy_px / divisor;
  camera.cx_px = d.cx_px / divisor;
  camera.cy_px = d.cy_px / divisor;
}

}  // namespace vigs::test
