#pragma once
// `vigs eval run`: the evaluation report of one pipeline run. What it measures now: ATE and
// RPE of RESULTS_DIR/trajectory.tum against the recording's ground truth, with PNG plots
// (trajectory top view against ground truth, ATE over time) drawn by gnuplot. What it states
// as not measured: PSNR/SSIM, rendered views, frame rate, peak memory and Gaussian count
// (they need the mapping and pipeline outputs) and LPIPS (needs network weights that cannot be
// fetched here).
#include <string>
#include <vector>

#include "core/geometry/se3.hpp"
#include "eval/ate.hpp"
#include "eval/rpe.hpp"

namespace vigs::eval {

struct ReportOptions {
  std::string results_dir;
  std::string gt_path;                           ///< .mcap (ground-truth topic) or TUM/KITTI
  std::string estimate_name = "trajectory.tum";  ///< inside results_dir
  /// The estimate is of the camera (T_w_c): ground-truth body poses become camera poses
  /// T_w_b T_b_c before comparison. false: the estimate is of the body (IMU) frame.
  bool estimate_is_camera = true;
  geometry::Pose T_b_c = geometry::Pose::Identity();
  AteOptions ate;
  double rpe_delta_m = 1.0;  ///< RPE over 1 m of path (and separately over one frame)
  bool plots = true;
};

struct ReportResult {
  std::string report_path;
  std::vector<std::string> plots;     ///< PNGs written
  std::vector<std::string> warnings;  ///< e.g. gnuplot missing
  AteResult ate;
  RpeResult rpe_frame, rpe_metre;
};

/// Writes RESULTS_DIR/report.md (atomically) and the plots. Throws TrajectoryFileError or
/// std::invalid_argument on unusable inputs, std::runtime_error when a file cannot be written.
ReportResult write_report(const ReportOptions& opt);

/// The JSON printed by `vigs eval run`.
std::string report_json(const ReportResult& r, const ReportOptions& opt);

}  // namespace vigs::eval
