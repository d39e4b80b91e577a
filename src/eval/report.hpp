#pragma once
// `vigs eval run`: the evaluation report of one pipeline run, from a RESULTS_DIR laid out as in
// eval/results_dir.hpp (trajectory.tum required; map.ply, keyframes.txt, stats.json optional).
// It measures ATE and RPE of trajectory.tum against the ground truth (PNG plots by gnuplot:
// trajectory top view, ATE over time); with map.ply and an MCAP ground truth, PSNR and SSIM of
// the map rendered at the estimated poses against the recorded colour images, on every 5th
// frame and on held-out frames never used as keyframes (eval/render_quality.hpp), and a PNG of
// rendered views beside the recording; the Gaussian count from map.ply; frame rate and peak
// memory from stats.json. Whatever an absent file would have given is listed as not measured,
// and so is LPIPS (it needs network weights that cannot be fetched here).
#include <string>
#include <vector>

#include "core/geometry/se3.hpp"
#include "eval/ate.hpp"
#include "eval/render_quality.hpp"
#include "eval/rpe.hpp"
#include "pipeline/results_dir.hpp"

namespace vigs::eval {

struct ReportOptions {
  std::string results_dir;
  /// The RESULTS_DIR report.md names (empty: results_dir): where the folder will be when
  /// results_dir is a temporary one renamed into place after the report (`vigs run`).
  std::string shown_dir;
  std::string gt_path;                           ///< .mcap (ground-truth topic) or TUM/KITTI
  std::string estimate_name = "trajectory.tum";  ///< inside results_dir
  /// The estimate is of the camera (T_w_c): ground-truth body poses become camera poses
  /// T_w_b T_b_c before comparison. false: the estimate is of the body (IMU) frame.
  bool estimate_is_camera = true;
  geometry::Pose T_b_c = geometry::Pose::Identity();
  AteOptions ate;
  double rpe_delta_m = 1.0;  ///< RPE over 1 m of path (and separately over one frame)
  bool plots = true;
  bool render = true;  ///< PSNR/SSIM and rendered views (needs map.ply and a .mcap ground truth)
  RenderQualityOptions quality;  ///< side_by_side_png is set by write_report
};

struct ReportResult {
  std::string report_path;
  std::vector<std::string> plots;     ///< PNGs written
  std::vector<std::string> warnings;  ///< e.g. gnuplot missing
  AteResult ate;
  RpeResult rpe_frame, rpe_metre;
  bool quality_measured = false;
  RenderQuality quality;
  /// The map was rendered at the ground truth's camera poses, not the estimate's: the run
  /// built it at them (stats.json map_poses "ground_truth", `vigs replay --map-poses`).
  bool rendered_at_ground_truth = false;
  bool have_keyframes = false;       ///< keyframes.txt was present
  std::vector<double> keyframe_t_s;  ///< from keyframes.txt
  long gaussians = -1;               ///< from map.ply, -1 when not read
  pipeline::RunStats run_stats;
  std::vector<std::string> missing;     ///< optional RESULTS_DIR files absent
  io::mcap::DamageReport input_damage;  ///< of the ground-truth recording (also in warnings)
  std::string input_damage_used;        ///< what of it was used
};

/// Writes RESULTS_DIR/report.md (atomically) and the plots. Throws TrajectoryFileError or
/// std::invalid_argument on unusable inputs, std::runtime_error when a file cannot be written.
ReportResult write_report(const ReportOptions& opt);

/// The JSON printed by `vigs eval run`.
std::string report_json(const ReportResult& r, const ReportOptions& opt);

}  // namespace vigs::eval
