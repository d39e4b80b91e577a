#pragma once
// The tracking components' settings, declared once: each default is written here and each
// field's unit, range and doc string in TrackingSettings::visit (tracking_settings.hpp), which
// binds them to the robot file's flat `tracking:` keys. The components name them as their
// nested `Setting` (DepthToPoints::Setting is DepthToPointsSetting, Gicp::Setting is
// GicpSetting, ...). Fields the robot file does not set carry their doc here.
#include <array>
#include <string_view>

namespace vigs::config {

/// Degrees to radians, as the tracking components convert their angle settings.
constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

/// Covariance regularisation (tracking/covariance.hpp).
enum class Regularization { normalized_ellipse, plane, none };
inline constexpr std::array<std::string_view, 3> kRegularizationNames{"normalized_ellipse", "plane",
                                                                      "none"};

/// How the k nearest neighbours are found. Both give the exact kNN (they may differ only in
/// which of several equidistant points is kept).
enum class KnnSearch {
  image_grid,  ///< through the depth image (organized_knn.hpp), kd-tree where uncertified
  kd_tree,     ///< kd-tree over the points (kdtree.hpp)
};
inline constexpr std::array<std::string_view, 2> kKnnSearchNames{"image_grid", "kdtree"};

/// Robust kernel on the GICP residual (tracking/gicp_factor.hpp).
enum class RobustKernel { none, huber, cauchy, geman_mcclure };
inline constexpr std::array<std::string_view, 4> kRobustKernelNames{"none", "huber", "cauchy",
                                                                    "geman_mcclure"};

/// Where GICP starts for a new frame (tracking/initial_guess.hpp).
enum class InitialGuessMode { imu, constant_velocity, previous_pose };
inline constexpr std::array<std::string_view, 3> kInitialGuessNames{"imu", "constant_velocity",
                                                                    "previous_pose"};

/// DepthToPoints::Setting.
struct DepthToPointsSetting {
  int pixel_stride = 4;  ///< starting at pixel (0, 0)
  double voxel_size_m = 0.0;
  double near_m = 0.1;
  double far_m = 8.0;
};

/// tracking::CovarianceSetting.
struct CovarianceSetting {
  int k_neighbors = 10;  ///< includes the point itself, as GS-ICP SLAM's kd-tree query does
  Regularization regularization = Regularization::normalized_ellipse;
  double epsilon = 1e-3;
  KnnSearch knn_search = KnnSearch::image_grid;
};

/// KdTree::Setting (not in the robot file).
struct KdTreeSetting {
  int leaf_size = 16;  ///< most points per leaf (bench_tracking BM_KnnOwnKdTree/LEAF)
};

/// FramePreprocessor::Setting.
struct PreprocessSetting {
  DepthToPointsSetting depth;
  CovarianceSetting covariance;
  KdTreeSetting tree;
};

/// Gicp::Setting.
struct GicpSetting {
  double max_correspondence_distance_m = 0.1;
  RobustKernel kernel = RobustKernel::huber;
  double kernel_width = 0.5;
  int max_iterations = 30;
  double rotation_eps_deg = 0.1;
  double translation_eps_m = 1e-3;
  double lm_lambda_init = 1e-6;  ///< initial damping of H + lambda I (not in the robot file)
  /// The Hessian's rotations are re-expressed about the centroid of the matched points and
  /// scaled by the RMS spread about it (gicp_impl.hpp). A single plane gives about epsilon.
  double degenerate_eigen_ratio = 1e-2;
  double overlap_distance_m = 0.022;  ///< for GicpResult::overlap_ratio
  int min_inliers = 20;               ///< fewer correspondences: diverged (not in the robot file)
  int num_threads = 2;

  [[nodiscard]] double rotation_eps_rad() const { return rotation_eps_deg * kRadPerDeg; }
};

/// LocalMap::Setting.
struct LocalMapSetting {
  double voxel_m = 0.1;
  int points_per_voxel = 20;
  int max_voxels = 16384;
  double radius_m = 6.0;
  double confirm_distance_m = 0.0;
  int confirm_keyframes = 3;
  /// A full voxel swaps its farthest-seen point for a new one seen from nearer than this
  /// fraction of that point's depth (depth noise grows with depth); 0 = keep the first points.
  /// 0.7: 3 minutes at 720x480, lockstep, 12 people seed 3 0.123 -> 0.077 m ATE and 24 people
  /// 0.132 -> 0.078 m (BENCHMARKS.md, eighteenth session).
  double replace_depth_ratio = 0.7;
};

/// KeyframePolicy::Setting.
struct KeyframeSetting {
  double min_overlap_ratio = 0.7;  ///< GS-ICP SLAM's keyframe_th
  double max_translation_m = 0.3;
  double max_rotation_deg = 15.0;

  [[nodiscard]] double max_rotation_rad() const { return max_rotation_deg * kRadPerDeg; }
};

/// tracking::LoopCloser (tracking/loop_closure.hpp): keyframes that come back within
/// search_radius_m of a keyframe at least min_age_s older, looking the same way, are registered
/// to it by GICP; verified ones become loop edges of a keyframe pose graph whose solution
/// corrects the run's trajectory.
struct LoopClosureSetting {
  /// On: 3 minutes of the 12-people office, lockstep, 0.240 -> 0.170 m ATE (paper) and
  /// 0.276 -> 0.221 m (fused), with no loop refused wrongly (BENCHMARKS.md).
  bool enabled = true;
  double min_age_s = 30.0;           ///< an older keyframe than this is a loop candidate
  double search_radius_m = 2.0;      ///< candidate within this of the keyframe's estimate
  double max_view_angle_deg = 30.0;  ///< and optical axes within this angle
  double anchor_spacing_m = 1.0;     ///< a keyframe's cloud is kept this far from the last kept
  double min_inlier_ratio = 0.35;    ///< verification: GICP inliers within 1.5 cloud voxels
  double cloud_voxel_m = 0.08;       ///< kept clouds: one static point per voxel this wide
  /// Memory the kept clouds may hold (about 0.3 MB a metre of new path at 720x480); beyond it
  /// the most redundant anchor (nearest to another seen the same way) is dropped.
  double max_anchor_mb = 256.0;
};

/// What Tracker::Setting holds beyond its threads (tracking/tracker.hpp).
struct TrackerSetting {
  PreprocessSetting preprocess;
  /// Against a local map in a place with walking people (uHumans), the tracker's GICP departs
  /// from the generic defaults above: matches within 5 cm only, and a bounded kernel
  /// (Geman-McClure), so a person matched to the wall behind him pulls almost nothing.
  GicpSetting gicp = [] {
    GicpSetting g;
    g.max_correspondence_distance_m = 0.05;
    g.kernel = RobustKernel::geman_mcclure;
    return g;
  }();
  /// A local-map point is used once a later keyframe re-observed it within 5 cm: a walking
  /// person is not where he was a keyframe ago.
  LocalMapSetting local_map = [] {
    LocalMapSetting m;
    m.confirm_distance_m = 0.05;
    return m;
  }();
  KeyframeSetting keyframe;
  InitialGuessMode initial_guess = InitialGuessMode::imu;
  double min_inlier_ratio = 0.3;
  double max_correction_m = 0.5;
  double max_correction_deg = 30.0;
  /// GicpResult::information / this = metric information. 0.1 (measured, BENCHMARKS.md issue
  /// #11, 2026-12-04): at 1 (and 0.3) the fused filter's prior outweighed GICP along a
  /// corridor's axis after a corner in real time, and its velocity ran 30 % fast until the
  /// track was lost.
  double gicp_variance_scale = 0.1;
  /// GICP aligns every n-th cell of the frame's pixel grid in x and y (every n^2-th point of
  /// an unorganised cloud); covariances, the local map and keyframes keep every point.
  int gicp_source_stride = 2;
  /// Moving-point test at keyframes (tracking/frame_history.hpp, Keyframe::moving): a point is
  /// moving when one of the `moving_window_frames` frames before or after the keyframe measured
  /// a surface more than this behind it along its ray. 0 = off.
  double moving_margin_m = 0.15;
  /// Frames before and after a keyframe it is compared with; the keyframe enters the local map
  /// (and reaches the mapper) this many frames late. 0 = off.
  int moving_window_frames = 4;
  /// After this many consecutive lost frames the local map is dropped and restarted from the
  /// current frame at its guess (the IMU-propagated pose in imu mode), as at the first frame:
  /// the track goes on with the drift of the lost stretch instead of never matching the old
  /// map again; the odometry starts the IMU state again there too (at rest). 0 = never.
  /// Default 10 (0.5 s at 20 Hz): the restart used to keep the velocity the IMU alone had
  /// carried through the lost frames, so it was lost again at once (214 restarts in a 3-minute
  /// run); with the IMU state restarted, the as-run replays of two real-time runs that lost the
  /// track under load end at 33 m and 14 m ATE instead of 2.9 km and 3.4 km (BENCHMARKS.md, Live
  /// pipeline, sixth session). A run that never loses 10 frames in a row is unchanged.
  int reinit_after_lost_frames = 10;

  [[nodiscard]] double max_correction_rad() const { return max_correction_deg * kRadPerDeg; }
  [[nodiscard]] bool moving_test_on() const {
    return moving_margin_m > 0.0 && moving_window_frames > 0;
  }
  /// Keyframes the tracker can hold at once for the moving test (a keyframe at most every
  /// frame, each held moving_window_frames frames): moving_window_frames + 1, or 0 when off.
  [[nodiscard]] int held_keyframes() const {
    return moving_test_on() ? moving_window_frames + 1 : 0;
  }
};

}  // namespace vigs::config
