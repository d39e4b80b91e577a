#pragma once
// Relative pose error (Sturm et al. 2012, as TUM evaluate_rpe.py with every start pose):
// for each associated pose i and the pose j one delta later, E = (G_i^-1 G_j)^-1 (P_i^-1 P_j);
// the statistics are over |trans(E)| and angle(E).
#include <string>

#include "eval/error_stats.hpp"
#include "eval/trajectory.hpp"
#include "eval/umeyama.hpp"

namespace vigs::eval {

enum class DeltaUnit { kFrames, kMetres, kSeconds };

struct RpeOptions {
  /// frames (integer >= 1), metres of ground-truth path, or seconds (TUM evaluate_rpe.py's
  /// default unit: the first pose at least delta seconds later)
  double delta = 1.0;
  DeltaUnit unit = DeltaUnit::kFrames;
  double max_dt_s = 0.02;  ///< association window
  /// none or se3: relative motion is unaffected by a rigid alignment. sim3: the estimate's
  /// translations are scaled by the Umeyama scale first (monocular estimates).
  Alignment align = Alignment::kNone;
};

struct RpeResult {
  std::size_t associated = 0;  ///< associated poses
  std::size_t pairs = 0;       ///< (i, j) pairs evaluated
  double scale = 1.0;
  ErrorStats translation_m;
  ErrorStats rotation_deg;
};

/// Throws std::invalid_argument when no pair is one delta apart.
RpeResult compute_rpe(const Trajectory& gt, const Trajectory& est, const RpeOptions& opt);

io::Json rpe_to_json(const RpeResult& r, const RpeOptions& opt);
/// rpe_to_json on one line; throws io::JsonNonFiniteError if a figure is NaN/Inf.
std::string rpe_json(const RpeResult& r, const RpeOptions& opt);

}  // namespace vigs::eval
