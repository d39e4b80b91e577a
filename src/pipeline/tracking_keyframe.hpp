#pragma once
// Adapter from the tracker's keyframe (tracking/gaussian_cloud.hpp, a plain data header) to the
// mapper's insertion input. The RAW kNN covariances are used: rotation from their
// eigenvectors, and with a sample angle the footprint-sized scale and depth-confidence opacity
// of mapping/insertion.hpp (without, GS-ICP SLAM's scales: square roots of the eigenvalues
// divided by max(1, 2 z^1.5)). Points the tracker flagged moving (Keyframe::moving) are left
// out. In the pipeline, which joins the two, so that neither mapping nor
// tracking knows the other.
#include <algorithm>

#include "core/types/pinhole_camera.hpp"
#include "mapping/keyframe_gaussians.hpp"
#include "tracking/gaussian_cloud.hpp"

namespace vigs::pipeline {

/// The angle between neighbouring samples of a keyframe's points: the tracker's pixel stride
/// over the mean focal length.
inline double keyframe_sample_angle_rad(const PinholeCamera& camera, int tracker_pixel_stride) {
  return 2.0 * std::max(1, tracker_pixel_stride) / (camera.fx_px + camera.fy_px);
}

/// Copies (allocates): call on the mapper side, not on the tracker thread. `sample_angle_rad`:
/// keyframe_sample_angle_rad() (mapping/insertion.hpp: footprint-sized Gaussians); 0 keeps the
/// GS-ICP SLAM scale rule. No default: the live mapper once left it out and inserted every
/// real-time keyframe with GS-ICP SLAM's far smaller scales (a speckled map, 15 dB).
inline mapping::KeyframeGaussians to_keyframe_gaussians(const tracking::Keyframe& kf,
                                                        double sample_angle_rad) {
  mapping::KeyframeGaussians out;
  out.T_w_c = kf.T_w_c;
  out.sample_angle_rad = sample_angle_rad;
  const tracking::GaussianCloud& c = kf.cloud_c;
  const bool flags = kf.moving.size() == c.size();
  out.points_c.reserve(c.size());
  out.covariances_c.reserve(c.size());
  out.colors.reserve(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (flags && kf.moving[i] != 0) continue;  // a walking person: not a map surface
    out.points_c.push_back(c.points_m[i]);
    out.covariances_c.push_back(c.cov_raw_m2[i]);
    const auto& rgb = c.colors_rgb[i];
    out.colors.emplace_back(rgb[0] / 255.0f, rgb[1] / 255.0f, rgb[2] / 255.0f);
  }
  return out;
}

}  // namespace vigs::pipeline
