#pragma once
// Depth image to camera-frame points with colour: pinhole back-projection, near/far
// truncation, pixel-stride sampling and optional voxel-grid averaging. Invalid depth
// (NaN, zero, negative) and out-of-range depth are skipped and counted.
#include <cstdint>
#include <utility>
#include <vector>

#include "core/types/pinhole_camera.hpp"
#include "io/image.hpp"
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
  struct Setting {
    int pixel_stride = 4;       ///< every n-th pixel in x and y, starting at (0, 0)
    double voxel_size_m = 0.0;  ///< average points per voxel of this edge; 0 = off
    double near_m = 0.1;
    double far_m = 8.0;
  };

  DepthToPoints() = default;
  DepthToPoints(const PinholeCamera& camera, const Setting& setting)
      : camera_(camera), setting_(setting) {}

  /// Depth in metres (e.g. io::read_depth_m). `rgb` is empty or a 3-channel image of the same
  /// size; without it colours are 0. Output: points_m and colors_rgb of `out` (covariances are
  /// cleared). With `grid`, also where each point came from (cleared when the voxel grid
  /// resamples the cloud). Throws std::invalid_argument on mismatched image sizes.
  DepthToPointsStats convert(const io::ImageF32& depth_m, const io::ImageU8& rgb,
                             GaussianCloud& out, PixelGrid* grid = nullptr);
  /// Raw 16-bit depth times `depth_scale_m` (0.001 for millimetres).
  DepthToPointsStats convert(const io::ImageU16& depth_raw, double depth_scale_m,
                             const io::ImageU8& rgb, GaussianCloud& out, PixelGrid* grid = nullptr);

  [[nodiscard]] const Setting& setting() const { return setting_; }
  [[nodiscard]] const PinholeCamera& camera() const { return camera_; }

 private:
  template <class DepthAt>
  DepthToPointsStats convert_impl(int width, int height, DepthAt depth_at, const io::ImageU8& rgb,
                                  GaussianCloud& out, PixelGrid* grid);
  void voxel_average(GaussianCloud& out);

  PinholeCamera camera_;
  Setting setting_;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> voxel_keys_;  // scratch, reused
};

}  // namespace vigs::tracking
