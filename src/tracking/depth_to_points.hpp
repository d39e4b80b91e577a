#pragma once
// Depth image to camera-frame points with colour: pinhole back-projection, near/far
// truncation, pixel-stride sampling and optional voxel-grid averaging. Invalid depth
// (NaN, zero, negative) and out-of-range depth are skipped and counted.
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/config/tracking_components.hpp"
#include "core/types/image.hpp"
#include "core/types/pinhole_camera.hpp"
#include "core/types/rgbd_view.hpp"
#include "tracking/gaussian_cloud.hpp"
#include "tracking/pixel_grid.hpp"

namespace vigs::tracking {

struct DepthToPointsStats {
  int sampled = 0;   ///< pixels visited (after the stride)
  int invalid = 0;   ///< NaN, zero or negative depth
  int too_near = 0;  ///< depth < near_m
  int too_far = 0;   ///< depth > far_m
  int points = 0;    ///< points produced (after the voxel grid)
};

class DepthToPoints {
 public:
  using Setting = config::DepthToPointsSetting;

  DepthToPoints() = default;
  /// With the voxel grid on, its scratch is sized for a whole frame here (convert() then does
  /// not allocate on a real-time thread).
  DepthToPoints(const PinholeCamera& camera, const Setting& setting);

  /// One frame's depth (metres, or raw units times the view's scale) and colour (black when
  /// the view has none). Output: points_m and colors_rgb of `out` (covariances are cleared).
  /// With `grid`, also where each point came from (cleared when the voxel grid resamples the
  /// cloud). Throws std::invalid_argument when the frame is empty or differs from the camera's
  /// size.
  DepthToPointsStats convert(const RgbdView& frame, GaussianCloud& out, PixelGrid* grid = nullptr);
  /// Owned images (tools, tests): depth in metres (e.g. io::read_depth_m); `rgb` empty or of
  /// the same size (3 channels, or 1 read as grey).
  DepthToPointsStats convert(const ImageF32& depth_m, const ImageU8& rgb, GaussianCloud& out,
                             PixelGrid* grid = nullptr) {
    if (depth_m.empty()) throw std::invalid_argument("depth image is empty");
    return convert(rgbd_view(0, depth_m, rgb), out, grid);
  }
  /// Raw 16-bit depth times `depth_scale_m` (0.001 for millimetres), in single precision.
  DepthToPointsStats convert(const ImageU16& depth_raw, double depth_scale_m, const ImageU8& rgb,
                             GaussianCloud& out, PixelGrid* grid = nullptr) {
    if (depth_raw.empty()) throw std::invalid_argument("depth image is empty");
    return convert(rgbd_view(0, depth_raw, static_cast<float>(depth_scale_m), rgb), out, grid);
  }

  [[nodiscard]] const Setting& setting() const { return setting_; }
  [[nodiscard]] const PinholeCamera& camera() const { return camera_; }
  /// The most points a frame can give (every stride-th pixel valid), before the voxel grid.
  [[nodiscard]] std::size_t max_points() const;

 private:
  template <class DepthAt>
  DepthToPointsStats convert_impl(const RgbdView& frame, DepthAt depth_at, GaussianCloud& out,
                                  PixelGrid* grid);
  void voxel_average(GaussianCloud& out);

  PinholeCamera camera_;
  Setting setting_;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> voxel_keys_;  // scratch, reused
};

}  // namespace vigs::tracking
