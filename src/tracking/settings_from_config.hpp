#pragma once
// The robot file's `tracking:` section (core/config/tracking_settings.hpp) mapped onto the
// nested Setting structs of the tracking components.
#include <string>

#include "core/config/tracking_settings.hpp"
#include "tracking/gicp.hpp"
#include "tracking/preprocess.hpp"
#include "tracking/tracker.hpp"

namespace vigs::tracking {

inline Regularization regularization_from_string(const std::string& name) {
  if (name == "plane") return Regularization::plane;
  if (name == "none") return Regularization::none;
  return Regularization::normalized_ellipse;  // the config loader admits only the three names
}

inline RobustKernel kernel_from_string(const std::string& name) {
  if (name == "huber") return RobustKernel::huber;
  if (name == "cauchy") return RobustKernel::cauchy;
  if (name == "geman_mcclure") return RobustKernel::geman_mcclure;
  return RobustKernel::none;
}

inline FramePreprocessor::Setting preprocess_setting(const config::TrackingSettings& c) {
  FramePreprocessor::Setting s;
  s.depth.pixel_stride = c.pixel_stride;
  s.depth.voxel_size_m = c.voxel_size_m;
  s.depth.near_m = c.near_m;
  s.depth.far_m = c.far_m;
  s.covariance.k_neighbors = c.k_neighbors;
  s.covariance.regularization = regularization_from_string(c.regularization);
  s.covariance.knn_search = c.knn_search == "kdtree" ? KnnSearch::kd_tree : KnnSearch::image_grid;
  s.covariance.epsilon = c.regularization_epsilon;
  return s;
}

inline Gicp::Setting gicp_setting(const config::TrackingSettings& c) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  Gicp::Setting s;
  s.max_correspondence_distance_m = c.max_correspondence_distance_m;
  s.kernel = kernel_from_string(c.robust_kernel);
  s.kernel_width = c.robust_kernel_width;
  s.max_iterations = c.max_iterations;
  s.rotation_eps_rad = c.rotation_eps_deg * kDeg;
  s.translation_eps_m = c.translation_eps_m;
  s.degenerate_eigen_ratio = c.degenerate_eigen_ratio;
  s.overlap_distance_m = c.keyframe_overlap_distance_m;
  s.num_threads = c.num_threads;
  return s;
}

inline Tracker::Setting tracker_setting(const config::TrackingSettings& c) {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  Tracker::Setting s;
  s.preprocess = preprocess_setting(c);
  s.gicp = gicp_setting(c);
  s.local_map.voxel_m = c.local_map_voxel_m;
  s.local_map.points_per_voxel = c.local_map_points_per_voxel;
  s.local_map.max_voxels = c.local_map_max_voxels;
  s.local_map.radius_m = c.local_map_radius_m;
  s.local_map.confirm_distance_m = c.local_map_confirm_distance_m;
  s.local_map.confirm_keyframes = c.local_map_confirm_keyframes;
  s.moving_margin_m = c.moving_margin_m;
  s.moving_window_frames = c.moving_window_frames;
  s.gicp_variance_scale = c.gicp_variance_scale;
  s.keyframe.min_overlap_ratio = c.keyframe_overlap_ratio;
  s.keyframe.max_translation_m = c.keyframe_translation_m;
  s.keyframe.max_rotation_rad = c.keyframe_rotation_deg * kDeg;
  s.initial_guess = initial_guess_from_string(c.initial_guess);
  s.min_inlier_ratio = c.min_inlier_ratio;
  s.max_correction_m = c.max_correction_m;
  s.max_correction_rad = c.max_correction_deg * kDeg;
  s.preprocess_threads = c.num_threads;
  return s;
}

}  // namespace vigs::tracking
