#pragma once
// Adapter from the tracker's keyframe (tracking/gaussian_cloud.hpp, a plain data header) to the
// mapper's insertion input. The RAW kNN covariances are used, as GS-ICP SLAM does: scales from
// the square roots of their eigenvalues (then divided by max(1, 2 z^1.5) at insertion), rotation
// from their eigenvectors. Points the tracker flagged moving (Keyframe::moving) are left out.
// In the pipeline, which joins the two, so that neither mapping nor
// tracking knows the other.
#include "mapping/keyframe_gaussians.hpp"
#include "tracking/gaussian_cloud.hpp"

namespace vigs::pipeline {

/// Copies (allocates): call on the mapper side, not on the tracker thread.
inline mapping::KeyframeGaussians to_keyframe_gaussians(const tracking::Keyframe& kf) {
  mapping::KeyframeGaussians out;
  out.T_w_c = kf.T_w_c;
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
