#pragma once
// The RESULTS_DIR contract: what a pipeline run leaves behind for `vigs eval run`. Here, with
// the producer (results_writer.hpp), so the pipeline does not link the evaluation, which reads it.
//
//   trajectory.tum  required. Estimated camera poses T_w_c, one TUM line per frame
//                   (`t tx ty tz qx qy qz qw`, seconds and metres, Hamilton quaternion).
//   trajectory_odometry.tum  optional (runs with tracking.loop_closure). The poses as the
//                   odometry tracked them, before the loop closer's correction, which
//                   trajectory.tum then holds; `vigs eval run --estimate` compares either.
//                   map.ply follows the correction (each keyframe's Gaussians move with it,
//                   pipeline/map_loop_correction.hpp), so it is in trajectory.tum's frame.
//   map.ply         optional. The Gaussian map in the standard 3DGS PLY layout
//                   (mapping/ply_io.hpp), in the same world frame as trajectory.tum.
//                   Without it there are no PSNR/SSIM, rendered views or Gaussian count.
//   keyframes.txt   optional. Timestamps (s, first number on each line; '#' comments and blank
//                   lines skipped) of the frames the run used as keyframes. Without it the
//                   held-out set (frames never used as keyframes) cannot be formed.
//   stats.json      optional. One JSON object; the report reads these numeric keys, each
//                   optional: "frames", "wall_s", "fps", "peak_rss_bytes", "gaussians".
//                   Other keys (any JSON value) are ignored. A missing key is reported as not
//                   measured; fps is derived from frames / wall_s only when both are given.
//
// Missing optional files are named in the report; no number is ever filled in for them.
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace vigs::pipeline {

inline constexpr const char* kTrajectoryFile = "trajectory.tum";
inline constexpr const char* kOdometryTrajectoryFile = "trajectory_odometry.tum";
inline constexpr const char* kMapFile = "map.ply";
inline constexpr const char* kKeyframesFile = "keyframes.txt";
inline constexpr const char* kStatsFile = "stats.json";

class ResultsFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What the producer measured about its own run (stats.json).
struct RunStats {
  std::optional<double> frames;
  std::optional<double> wall_s;
  std::optional<double> fps;
  std::optional<double> peak_rss_bytes;
  std::optional<double> gaussians;
  /// Where the run put its keyframes into the map (`vigs replay --map-poses`): "estimate" or
  /// "ground_truth"; absent (older results, live runs): the estimate.
  std::optional<std::string> map_poses;
};

/// Parses stats.json text; `name` is used in messages. Throws ResultsFileError naming the file
/// and byte offset on malformed JSON, or the key when a known key is not a number (null is
/// accepted as "not measured") or map_poses is neither "estimate" nor "ground_truth".
RunStats parse_run_stats(const std::string& text, const std::string& name);
RunStats read_run_stats(const std::string& path);

/// keyframes.txt: sorted timestamps. Throws ResultsFileError "PATH:LINE: ..." on a line whose
/// first field is not a finite number.
std::vector<double> read_keyframe_times(const std::string& path);

/// Formats keyframe timestamps as keyframes.txt text (shortest round-trip numbers).
std::string format_keyframe_times(const std::vector<double>& t_s);

}  // namespace vigs::pipeline
