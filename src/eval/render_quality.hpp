#pragma once
// Rendering quality of a run's Gaussian map: the map is rendered at the run's estimated camera
// pose of recorded frames and compared with the recorded colour image (PSNR with peak 255; SSIM
// with the Gaussian 11x11 window, sigma 1.5, population covariance, over valid windows, mean
// over channels: mapping/image_metrics.hpp). Two frame sets:
//   every n-th: recorded frames whose index (0-based, among all colour messages) is a multiple
//               of n, keyframes included;
//   held-out:   frames farther than keyframe_tol_s from every keyframe timestamp, of which every
//               n-th (counted among those frames only) is used.
// When the recording has a depth image for the frame, PSNR and SSIM are also given over the
// pixels with valid depth only (SSIM: windows whose centre pixel has depth), the parts of the
// scene a depth-fed map can hold. When the recording has the simulator's ground-truth person
// mask for the frame (io::topics::kDynamicMask), PSNR is also given over the pixels without a
// person, and over those with valid depth too: the map leaves walking people out by design, so
// frames with people close by would otherwise measure the people, not the map. Means are
// per-frame means (PSNR averaged in dB, as 3DGS SLAM papers report). Frames without an estimated
// pose within max_dt_s are skipped and counted. The map is rendered in its own world frame at
// the unaligned estimate (the map and the estimate share one frame).
#include <cstdint>
#include <string>
#include <vector>

#include "eval/trajectory.hpp"
#include "mapping/gaussian_map.hpp"

namespace vigs::eval {

struct RenderQualityOptions {
  int every = 5;                  ///< frame stride of both sets
  double max_dt_s = 0.02;         ///< frame stamp to estimated pose association window
  double keyframe_tol_s = 0.005;  ///< a frame this close to a keyframe stamp is that keyframe
  int threads = 2;                ///< rasterizer threads
  int side_by_side_rows = 3;      ///< frames in the rendered-vs-recorded PNG (0: none)
  std::string side_by_side_png;   ///< where to write it ("" = not written)
};

struct QualitySet {
  std::vector<double> t_s;  ///< stamps of the frames measured
  std::vector<double> psnr_db;
  std::vector<double> ssim;
  // Every vector below holds one value per t_s; NaN marks a frame where the figure was not
  // measured, and the means skip it.
  /// Over the pixels with valid depth: NaN for a frame without a depth image (or none valid).
  std::vector<double> psnr_valid_depth_db;
  std::vector<double> ssim_valid_depth;
  /// Over the pixels no person covers (the static scene), and over those that also have valid
  /// depth: NaN for a frame without a person mask (and without depth, the second).
  std::vector<double> psnr_static_db;
  std::vector<double> psnr_static_valid_depth_db;
  [[nodiscard]] std::size_t frames() const { return t_s.size(); }
  [[nodiscard]] std::size_t frames_with_depth() const;
  [[nodiscard]] std::size_t frames_with_dynamic_mask() const;
  /// Means over the frames with a value (NaN when none has).
  [[nodiscard]] double mean_psnr_static_db() const;
  [[nodiscard]] double mean_psnr_static_valid_depth_db() const;
  [[nodiscard]] double mean_psnr_db() const;
  [[nodiscard]] double mean_ssim() const;
  [[nodiscard]] double min_psnr_db() const;
  [[nodiscard]] double mean_psnr_valid_depth_db() const;
  [[nodiscard]] double mean_ssim_valid_depth() const;
};

struct RenderQuality {
  QualitySet every_nth, held_out;
  std::uint64_t recorded_frames = 0;
  std::uint64_t keyframe_frames = 0;      ///< recorded frames matching a keyframe stamp
  std::uint64_t frames_without_pose = 0;  ///< of the selected frames
  std::uint64_t frames_without_camera_info = 0;
  int image_width = 0, image_height = 0;
  std::string side_by_side_png;  ///< written file, "" if none
  int side_by_side_width = 0, side_by_side_height = 0;
  std::vector<double> side_by_side_t_s;  ///< stamps shown, top to bottom
  io::mcap::DamageReport damage;         ///< found in the recording; frames of the intact part
};

/// `T_w_c` is the estimate as camera poses, sorted by time; `keyframe_t_s` sorted, or null when
/// the run did not say which frames were keyframes (then the held-out set stays empty). Throws
/// std::runtime_error on unreadable recordings and std::invalid_argument on bad options.
RenderQuality measure_render_quality(const mapping::GaussianMap& map, const Trajectory& T_w_c,
                                     const std::vector<double>* keyframe_t_s,
                                     const std::string& mcap_path, const RenderQualityOptions& opt);

/// Markdown section (## Rendering quality ...) of the report; `at_ground_truth`: the frames
/// were rendered at the ground truth's camera poses (a map built at them), not the estimate's.
std::string render_quality_markdown(const RenderQuality& q, const RenderQualityOptions& opt,
                                    bool have_keyframes, const std::string& png_relative,
                                    bool at_ground_truth = false);

}  // namespace vigs::eval
