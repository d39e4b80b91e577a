#pragma once
// Absolute trajectory error: associate by timestamp, align the estimated positions onto the
// ground truth (Umeyama), and summarise |p_gt - (s R p_est + t)| over the pairs.
#include <string>
#include <vector>

#include "eval/association.hpp"
#include "eval/error_stats.hpp"
#include "eval/trajectory.hpp"
#include "eval/umeyama.hpp"

namespace vigs::eval {

struct AteOptions {
  Alignment align = Alignment::kSe3;
  double max_dt_s = 0.02;  ///< association window (TUM evaluate_ate.py default)
  double offset_s = 0.0;   ///< added to the estimate's stamps before matching
};

struct AteResult {
  std::size_t pairs = 0;
  ErrorStats stats;                      ///< metres
  Sim3 alignment;                        ///< maps estimate positions into the ground-truth frame
  std::vector<double> t_s;               ///< ground-truth stamp of each pair
  std::vector<double> error_m;           ///< per pair
  std::vector<Eigen::Vector3d> p_gt_m;   ///< per pair
  std::vector<Eigen::Vector3d> p_est_m;  ///< per pair, aligned
};

/// Throws std::invalid_argument when fewer than 3 pairs associate (or formats differ:
/// a KITTI file has no timestamps to match against a TUM file's).
AteResult compute_ate(const Trajectory& gt, const Trajectory& est, const AteOptions& opt);

/// One JSON object: pairs, rmse, mean, median, std, min, max, sse, align, scale.
io::Json ate_to_json(const AteResult& r, const AteOptions& opt);
/// ate_to_json on one line; throws io::JsonNonFiniteError if a figure is NaN/Inf.
std::string ate_json(const AteResult& r, const AteOptions& opt);

/// Associated (gt index, est index) pairs, with the format check shared by ATE and RPE.
std::vector<IndexPair> associate_trajectories(const Trajectory& gt, const Trajectory& est,
                                              double max_dt_s, double offset_s);

}  // namespace vigs::eval
