#pragma once
#include <string>

#include "core/config/visitor.hpp"

namespace vigs::config {

/// RGB-D tracking front end: depth to points, kNN covariances, GICP against the bounded local
/// map, keyframe policy, failure detection and the initial guess. The tracking library maps
/// these onto its nested `Setting` structs (tracking/settings_from_config.hpp).
struct TrackingSettings {
  // Depth to points.
  int pixel_stride = 4;       ///< use every n-th pixel in x and y
  double voxel_size_m = 0.0;  ///< voxel-grid downsampling after the stride; 0 = off
  double near_m = 0.1;        ///< nearer depth is skipped (counted)
  double far_m = 8.0;         ///< farther depth is skipped (counted)
  // Covariances.
  int k_neighbors = 10;                               ///< kNN for per-point covariances
  std::string regularization = "normalized_ellipse";  ///< normalized_ellipse | plane | none
  double regularization_epsilon = 1e-3;               ///< smallest eigenvalue (relative)
  std::string knn_search = "image_grid";              ///< image_grid | kdtree
  // GICP.
  double max_correspondence_distance_m = 0.1;  ///< farther nearest neighbours are outliers
  std::string robust_kernel = "huber";         ///< none | huber | cauchy | geman_mcclure
  double robust_kernel_width = 0.5;            ///< on sqrt(d^T M d)
  int max_iterations = 30;
  double rotation_eps_deg = 0.1;    ///< converged when |d rotation| is below this ...
  double translation_eps_m = 1e-3;  ///< ... and |d translation| is below this
  int num_threads = 2;              ///< fixed partition, fixed-order sum: bit-identical
  // Keyframes.
  double keyframe_overlap_ratio = 0.7;         ///< GS-ICP SLAM's keyframe_th
  double keyframe_overlap_distance_m = 0.022;  ///< GS-ICP's overlapped_th 5e-4 m^2, as m
  double keyframe_translation_m = 0.3;         ///< or when moved farther than this
  double keyframe_rotation_deg = 15.0;         ///< or turned more than this
  // Local map.
  double local_map_voxel_m = 0.1;             ///< voxel edge of the local map hash
  int local_map_points_per_voxel = 20;        ///< per-voxel capacity
  int local_map_max_voxels = 16384;           ///< bound: max points = voxels * points per voxel
  double local_map_radius_m = 6.0;            ///< voxels farther from the camera are evicted
  double local_map_confirm_distance_m = 0.0;  ///< re-observation distance confirming a point
  int local_map_confirm_keyframes = 3;        ///< unconfirmed points dropped after this many
  // Moving people.
  double moving_margin_m = 0.0;  ///< keyframe point this far in front of a recent frame: moving
  int moving_window_frames = 0;  ///< frames before and after a keyframe it is compared with
  // IMU/GICP fusion.
  std::string fusion = "paper";      ///< fused | paper
  double gicp_variance_scale = 1.0;  ///< GICP residuals: this many times their covariance
  // Initial guess and failure detection.
  std::string initial_guess = "imu";     ///< imu | constant_velocity | previous_pose
  double min_inlier_ratio = 0.3;         ///< below: tracking failure
  double degenerate_eigen_ratio = 1e-2;  ///< scaled-Hessian min/max eigenvalue below: degenerate
  double max_correction_m = 0.5;         ///< GICP correction of the guess beyond: diverged
  double max_correction_deg = 30.0;      ///< GICP rotation correction beyond: diverged

  void visit(Visitor& v) {
    v.field("pixel_stride", pixel_stride, {"px", 1, 64, "use every n-th pixel in x and y"});
    v.field("voxel_size_m", voxel_size_m,
            {"m", 0.0, 10.0, "voxel-grid downsampling after the stride; 0 = off"});
    v.field("near_m", near_m, {"m", 0.0, 100.0, "nearer depth is skipped and counted"});
    v.field("far_m", far_m, {"m", 0.01, 1000.0, "farther depth is skipped and counted"});
    v.field("k_neighbors", k_neighbors, {"-", 3, 64, "neighbours per point covariance"});
    v.field("regularization", regularization, {"normalized_ellipse", "plane", "none"},
            "covariance regularisation (GS-ICP SLAM's normalised ellipse, plane (1,1,eps), none)");
    v.field("regularization_epsilon", regularization_epsilon,
            {"-", 1e-9, 1.0, "smallest eigenvalue after regularisation (relative)"});
    v.field("knn_search", knn_search, {"image_grid", "kdtree"},
            "how covariance neighbours are found: through the depth image (exact, kd-tree where "
            "uncertified) or a kd-tree");
    v.field("max_correspondence_distance_m", max_correspondence_distance_m,
            {"m", 1e-4, 100.0, "nearest neighbours farther than this are outliers"});
    v.field("robust_kernel", robust_kernel, {"none", "huber", "cauchy", "geman_mcclure"},
            "robust kernel on the Mahalanobis distance (geman_mcclure: bounded, for moving "
            "people)");
    v.field("robust_kernel_width", robust_kernel_width,
            {"-", 1e-6, 1e6, "kernel width on sqrt(d^T M d)"});
    v.field("max_iterations", max_iterations, {"-", 1, 1000, "GICP iterations"});
    v.field("rotation_eps_deg", rotation_eps_deg,
            {"deg", 0.0, 10.0, "convergence: rotation increment below this"});
    v.field("translation_eps_m", translation_eps_m,
            {"m", 0.0, 1.0, "convergence: translation increment below this"});
    v.field(
        "num_threads", num_threads,
        {"-", 1, 64, "tracking threads: preprocessing and GICP (fixed partition, bit-identical)"});
    v.field("keyframe_overlap_ratio", keyframe_overlap_ratio,
            {"-", 0.0, 1.0, "new keyframe when the overlap with the map falls below this"});
    v.field("keyframe_overlap_distance_m", keyframe_overlap_distance_m,
            {"m", 1e-4, 1.0, "a source point overlaps if a map point is this close"});
    v.field("keyframe_translation_m", keyframe_translation_m,
            {"m", 0.0, 100.0, "new keyframe after this translation"});
    v.field("keyframe_rotation_deg", keyframe_rotation_deg,
            {"deg", 0.0, 180.0, "new keyframe after this rotation"});
    v.field("local_map_voxel_m", local_map_voxel_m,
            {"m", 0.01, 10.0, "voxel edge of the local map (>= max_correspondence_distance_m)"});
    v.field("local_map_points_per_voxel", local_map_points_per_voxel,
            {"-", 1, 256, "points kept per local-map voxel"});
    v.field("local_map_max_voxels", local_map_max_voxels,
            {"-", 16, 4194304, "local-map voxel capacity; least recently seen evicted beyond"});
    v.field("local_map_radius_m", local_map_radius_m,
            {"m", 0.1, 1000.0, "local-map voxels farther than this from the camera are evicted"});
    v.field("local_map_confirm_distance_m", local_map_confirm_distance_m,
            {"m", 0.0, 1.0,
             "a map point is used by GICP once a later keyframe has a point this close "
             "(moving people are not re-observed in place); 0 = every point at once"});
    v.field("local_map_confirm_keyframes", local_map_confirm_keyframes,
            {"keyframes", 1, 1000, "unconfirmed local-map points are dropped after this many"});
    v.field("moving_margin_m", moving_margin_m,
            {"m", 0.0, 10.0,
             "keyframe points this far in front of the surface a frame shortly before or after "
             "measured along their ray are moving (not inserted, flagged for the mapper); "
             "0 = off"});
    v.field("moving_window_frames", moving_window_frames,
            {"frames", 0, 64,
             "the moving test compares a keyframe with this many frames before and after it "
             "(the keyframe reaches the map that many frames late); 0 = off"});
    v.field("fusion", fusion, {"fused", "paper"},
            "imu guess: fused = the IMU prediction and its covariance are a prior factor in "
            "GICP and a 15-state filter (pose, velocity, gyro and accel bias) is updated from "
            "the result; paper = IMU guess, then reset from GICP (VIGS)");
    v.field("gicp_variance_scale", gicp_variance_scale,
            {"-", 1e-9, 1e9,
             "GICP residuals are this many times their modelled covariance: metric "
             "information = GICP Hessian / scale (fusion weight and exported covariance)"});
    v.field("initial_guess", initial_guess, {"imu", "constant_velocity", "previous_pose"},
            "GICP initial guess");
    v.field("min_inlier_ratio", min_inlier_ratio,
            {"-", 0.0, 1.0, "tracking failure below this inlier ratio"});
    v.field("degenerate_eigen_ratio", degenerate_eigen_ratio,
            {"-", 0.0, 1.0, "degenerate when min/max eigenvalue of the scaled Hessian is below"});
    v.field("max_correction_m", max_correction_m,
            {"m", 0.0, 100.0, "diverged when GICP moves the guess farther than this"});
    v.field("max_correction_deg", max_correction_deg,
            {"deg", 0.0, 180.0, "diverged when GICP turns the guess more than this"});
    v.require(near_m < far_m, "far_m", "far_m must exceed near_m");
    v.require(local_map_voxel_m >= max_correspondence_distance_m, "local_map_voxel_m",
              "local_map_voxel_m must be >= max_correspondence_distance_m (27-voxel search)");
  }
};

}  // namespace vigs::config
