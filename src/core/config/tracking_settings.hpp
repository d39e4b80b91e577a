#pragma once
#include <string>

#include "core/config/tracking_components.hpp"
#include "core/config/visitor.hpp"

namespace vigs::config {

/// RGB-D tracking front end: depth to points, kNN covariances, GICP against the bounded local
/// map, keyframe policy, failure detection and the initial guess. The robot file's flat
/// `tracking:` keys bind the tracking components' settings (tracking_components.hpp, where
/// the defaults are); the docs, units and ranges are here. The tracking library takes the
/// components' parts as they are (tracking/settings_from_config.hpp).
struct TrackingSettings : TrackerSetting {
  std::string fusion = "fused";  ///< pipeline/odometry.hpp
  LoopClosureSetting loop;       ///< tracking/loop_closure.hpp

  void visit(Visitor& v) {
    v.field("pixel_stride", preprocess.depth.pixel_stride,
            {"px", 1, 64, "use every n-th pixel in x and y"});
    v.field("voxel_size_m", preprocess.depth.voxel_size_m,
            {"m", 0.0, 10.0, "voxel-grid downsampling after the stride; 0 = off"});
    v.field("near_m", preprocess.depth.near_m,
            {"m", 0.0, 100.0, "nearer depth is skipped and counted"});
    v.field("far_m", preprocess.depth.far_m,
            {"m", 0.01, 1000.0, "farther depth is skipped and counted"});
    v.field("k_neighbors", preprocess.covariance.k_neighbors,
            {"-", 3, 64, "neighbours per point covariance"});
    v.field("regularization", preprocess.covariance.regularization, kRegularizationNames,
            "covariance regularisation (GS-ICP SLAM's normalised ellipse, plane (1,1,eps), none)");
    v.field("regularization_epsilon", preprocess.covariance.epsilon,
            {"-", 1e-9, 1.0, "smallest eigenvalue after regularisation (relative)"});
    v.field("knn_search", preprocess.covariance.knn_search, kKnnSearchNames,
            "how covariance neighbours are found: through the depth image (exact, kd-tree where "
            "uncertified) or a kd-tree");
    v.field("gicp_source_stride", gicp_source_stride,
            {"cells", 1, 16,
             "GICP aligns every n-th sampled point in x and y (n^2 fewer); covariances, the "
             "local map and keyframes keep every point"});
    v.field("max_correspondence_distance_m", gicp.max_correspondence_distance_m,
            {"m", 1e-4, 100.0, "nearest neighbours farther than this are outliers"});
    v.field("robust_kernel", gicp.kernel, kRobustKernelNames,
            "robust kernel on the Mahalanobis distance (geman_mcclure: bounded, for moving "
            "people)");
    v.field("robust_kernel_width", gicp.kernel_width,
            {"-", 1e-6, 1e6, "kernel width on sqrt(d^T M d)"});
    v.field("max_iterations", gicp.max_iterations, {"-", 1, 1000, "GICP iterations"});
    v.field("rotation_eps_deg", gicp.rotation_eps_deg,
            {"deg", 0.0, 10.0, "convergence: rotation increment below this"});
    v.field("translation_eps_m", gicp.translation_eps_m,
            {"m", 0.0, 1.0, "convergence: translation increment below this"});
    v.field(
        "num_threads", gicp.num_threads,
        {"-", 1, 64, "tracking threads: preprocessing and GICP (fixed partition, bit-identical)"});
    v.field("keyframe_overlap_ratio", keyframe.min_overlap_ratio,
            {"-", 0.0, 1.0, "new keyframe when the overlap with the map falls below this"});
    v.field("keyframe_overlap_distance_m", gicp.overlap_distance_m,
            {"m", 1e-4, 1.0, "a source point overlaps if a map point is this close"});
    v.field("keyframe_translation_m", keyframe.max_translation_m,
            {"m", 0.0, 100.0, "new keyframe after this translation"});
    v.field("keyframe_rotation_deg", keyframe.max_rotation_deg,
            {"deg", 0.0, 180.0, "new keyframe after this rotation"});
    v.field("local_map_voxel_m", local_map.voxel_m,
            {"m", 0.01, 10.0, "voxel edge of the local map (>= max_correspondence_distance_m)"});
    v.field("local_map_points_per_voxel", local_map.points_per_voxel,
            {"-", 1, 256, "points kept per local-map voxel"});
    v.field("local_map_max_voxels", local_map.max_voxels,
            {"-", 16, 4194304, "local-map voxel capacity; least recently seen evicted beyond"});
    v.field("local_map_radius_m", local_map.radius_m,
            {"m", 0.1, 1000.0, "local-map voxels farther than this from the camera are evicted"});
    v.field("local_map_confirm_distance_m", local_map.confirm_distance_m,
            {"m", 0.0, 1.0,
             "a map point is used by GICP once a later keyframe has a point this close "
             "(moving people are not re-observed in place); 0 = every point at once"});
    v.field("local_map_confirm_keyframes", local_map.confirm_keyframes,
            {"keyframes", 1, 1000, "unconfirmed local-map points are dropped after this many"});
    v.field("local_map_replace_depth_ratio", local_map.replace_depth_ratio,
            {"-", 0.0, 1.0,
             "a full voxel replaces its farthest-seen point by a new one seen from nearer than "
             "this fraction of that point's camera depth; 0 = the first points stay"});
    v.field("moving_margin_m", moving_margin_m,
            {"m", 0.0, 10.0,
             "keyframe points this far in front of the surface a frame shortly before or after "
             "measured along their ray are moving (not inserted, flagged for the mapper); "
             "0 = off"});
    v.field("moving_window_frames", moving_window_frames,
            {"frames", 0, 64,
             "the moving test compares a keyframe with this many frames before and after it "
             "(the keyframe reaches the map that many frames late); 0 = off"});
    v.field("reinit_after_lost_frames", reinit_after_lost_frames,
            {"frames", 0, 100000,
             "after this many consecutive lost frames the local map restarts from the current "
             "frame at its guess (IMU pose), and the IMU state restarts there at rest, as at the "
             "first frame; 0 = never"});
    v.field("fusion", fusion, {"fused", "paper"},
            "imu guess: fused (default) = the IMU prediction and its covariance are a prior "
            "factor in GICP and a 15-state filter (pose, velocity, gyro and accel bias) is "
            "updated from the result; paper = IMU guess, then reset from GICP (VIGS as "
            "published)");
    v.field("gicp_variance_scale", gicp_variance_scale,
            {"-", 1e-9, 1e9,
             "GICP residuals are this many times their modelled covariance: metric "
             "information = GICP Hessian / scale (fusion weight and exported covariance)"});
    v.field("initial_guess", initial_guess, kInitialGuessNames, "GICP initial guess");
    v.field("min_inlier_ratio", min_inlier_ratio,
            {"-", 0.0, 1.0, "tracking failure below this inlier ratio"});
    v.field("degenerate_eigen_ratio", gicp.degenerate_eigen_ratio,
            {"-", 0.0, 1.0, "degenerate when min/max eigenvalue of the scaled Hessian is below"});
    v.field("max_correction_m", max_correction_m,
            {"m", 0.0, 100.0, "diverged when GICP moves the guess farther than this"});
    v.field("max_correction_deg", max_correction_deg,
            {"deg", 0.0, 180.0, "diverged when GICP turns the guess more than this"});
    v.field("loop_closure", loop.enabled,
            "close loops: keyframes that return to an old place are registered to it and the "
            "run's trajectory is corrected by a keyframe pose graph (trajectory.tum; the live "
            "poses stay as tracked)");
    v.field("loop_min_age_s", loop.min_age_s,
            {"s", 0.0, 1e6, "a keyframe at least this much older is a loop candidate"});
    v.field("loop_search_radius_m", loop.search_radius_m,
            {"m", 0.01, 100.0, "loop candidates lie within this of the keyframe's estimate"});
    v.field("loop_max_view_angle_deg", loop.max_view_angle_deg,
            {"deg", 0.0, 180.0, "and look within this angle of its optical axis"});
    v.field("loop_anchor_spacing_m", loop.anchor_spacing_m,
            {"m", 0.0, 100.0,
             "a keyframe's cloud is kept as a loop candidate when no kept one seen within "
             "30 degrees of its view is this close"});
    v.field("loop_min_inlier_ratio", loop.min_inlier_ratio,
            {"-", 0.0, 1.0, "a loop is accepted when GICP matches this share of the points"});
    v.field("loop_cloud_voxel_m", loop.cloud_voxel_m,
            {"m", 0.01, 1.0,
             "loop clouds keep one static keyframe point per voxel this wide (verification "
             "matches within 1.5 voxels)"});
    v.field("loop_max_anchor_mb", loop.max_anchor_mb,
            {"MB", 1.0, 1e6,
             "memory of the kept loop clouds; beyond it the most redundant one (nearest to "
             "another seen the same way) is dropped"});
    v.require(preprocess.depth.near_m < preprocess.depth.far_m, "far_m",
              "far_m must exceed near_m");
    v.require(local_map.voxel_m >= gicp.max_correspondence_distance_m, "local_map_voxel_m",
              "local_map_voxel_m must be >= max_correspondence_distance_m (27-voxel search)");
  }
};

}  // namespace vigs::config
