#pragma once
// The tracker's per-frame product and the mapper's input: points with their kNN covariances
// and colours. Plain vectors (array of small structs per field), all the same length.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/geometry/se3.hpp"

namespace vigs::tracking {

/// Points of one RGB-D frame in the CAMERA frame of that frame (x right, y down, z forward),
/// metres. `cov_raw_m2[i]` is the kNN sample covariance of point i (m^2), exactly as estimated;
/// `cov_m2[i]` is the regularised covariance GICP uses (see covariance.hpp for its scale).
/// Both are handed to the mapper unchanged: GS-ICP SLAM initialises each Gaussian's scale
/// from the square roots of the raw covariance's eigenvalues and its rotation from the
/// eigenvectors. Colours are 8-bit RGB.
struct GaussianCloud {
  std::vector<Eigen::Vector3f> points_m;
  std::vector<Eigen::Matrix3f> cov_raw_m2;
  std::vector<Eigen::Matrix3f> cov_m2;
  std::vector<std::array<std::uint8_t, 3>> colors_rgb;

  [[nodiscard]] std::size_t size() const { return points_m.size(); }
  [[nodiscard]] bool empty() const { return points_m.empty(); }
  /// Keeps capacity, so a reused cloud does not allocate once warmed up.
  void clear() {
    points_m.clear();
    cov_raw_m2.clear();
    cov_m2.clear();
    colors_rgb.clear();
  }
  void reserve(std::size_t n) {
    points_m.reserve(n);
    cov_raw_m2.reserve(n);
    cov_m2.reserve(n);
    colors_rgb.reserve(n);
  }
};

/// A keyframe for the mapper: the frame's Gaussians (camera frame) and the camera pose in
/// world, T_w_c (p_w = T_w_c * p_c), at the frame's time stamp.
///
/// `moving[i]` (same length as the cloud) is 1 for a point the tracker rejected as moving: a
/// frame shortly before or after the keyframe measured a surface behind it along its ray by more
/// than tracking.moving_margin_m, i.e. saw free space where the point is, as a walking person
/// leaves (frame_history.hpp). Such points were not inserted into the tracker's local map and
/// the pipeline does not give them to the mapper. All zero when the test is off
/// (moving_margin_m = 0 or moving_window_frames = 0) or at the first keyframe.
struct Keyframe {
  std::int64_t t_ns = 0;
  geometry::Pose T_w_c = geometry::Pose::Identity();
  GaussianCloud cloud_c;
  std::vector<std::uint8_t> moving;
};

}  // namespace vigs::tracking
