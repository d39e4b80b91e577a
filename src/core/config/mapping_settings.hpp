#pragma once
#include "core/config/visitor.hpp"

namespace vigs::config {

/// Gaussian-splatting map: loss weights, Adam learning rates (GS-ICP SLAM defaults), pruning,
/// insertion and the mapper task's schedule.
struct MappingSettings {
  double lambda_ssim = 0.2;    ///< (1 - lambda) L1 + lambda (1 - SSIM)
  double lambda_depth = 0.1;   ///< weight of the depth L1 term
  double lr_mean = 4e-6;       ///< Adam step for positions, m
  double lr_log_scale = 5e-3;  ///< Adam step for log-scales
  double lr_quat = 1e-3;       ///< Adam step for quaternions
  double lr_opacity = 0.05;    ///< Adam step for opacity logits
  double lr_color = 2.5e-3;    ///< Adam step for colour
  int prune_every = 50;        ///< iterations between pruning passes
  double prune_min_opacity = 0.005;
  double prune_max_scale_m = 0.5;
  double insert_voxel_m = 0.02;  ///< one Gaussian per occupied voxel of this size
  double insert_opacity = 0.9;   ///< initial opacity of inserted Gaussians at full confidence
  double min_scale_m = 1e-4;     ///< floor on initial standard deviations
  int threads = 2;               ///< rasterizer worker threads
  double rate_hz = 10.0;         ///< mapper task rate
  int iterations_per_tick = 1;   ///< optimisation iterations per mapper tick (budget_ms 0)
  double budget_ms = 0.0;        ///< time per mapper tick; > 0 replaces iterations_per_tick
  int window_keyframes = 8;      ///< recent keyframes in the training window
  int random_keyframes = 2;      ///< older keyframes drawn at random per round

  void visit(Visitor& v) {
    v.field("lambda_ssim", lambda_ssim, {"-", 0.0, 1.0, "weight of (1 - SSIM) against L1"});
    v.field("lambda_depth", lambda_depth, {"1/m", 0.0, 100.0, "weight of the depth L1 term"});
    v.field("lr_mean", lr_mean, {"m", 0.0, 1.0, "Adam step size of positions"});
    v.field("lr_log_scale", lr_log_scale, {"-", 0.0, 1.0, "Adam step size of log-scales"});
    v.field("lr_quat", lr_quat, {"-", 0.0, 1.0, "Adam step size of quaternions"});
    v.field("lr_opacity", lr_opacity, {"-", 0.0, 1.0, "Adam step size of opacity logits"});
    v.field("lr_color", lr_color, {"-", 0.0, 1.0, "Adam step size of RGB colour"});
    v.field("prune_every", prune_every, {"iterations", 1, 100000, "pruning period"});
    v.field("prune_min_opacity", prune_min_opacity,
            {"-", 0.0, 1.0, "Gaussians below this opacity are pruned"});
    v.field("prune_max_scale_m", prune_max_scale_m,
            {"m", 0.001, 100.0, "Gaussians with a larger standard deviation are pruned"});
    v.field("insert_voxel_m", insert_voxel_m,
            {"m", 0.001, 1.0, "insertion skips voxels of this size that already hold a Gaussian"});
    v.field("insert_opacity", insert_opacity,
            {"-", 0.001, 0.99,
             "opacity of new Gaussians at full depth confidence (lower where the sample's "
             "covariance is thick against its footprint); the flat opacity without a sample "
             "angle"});
    v.field("min_scale_m", min_scale_m, {"m", 1e-6, 1.0, "floor on initial standard deviations"});
    v.field("threads", threads, {"threads", 1, 64, "rasterizer worker threads"});
    v.field("rate_hz", rate_hz, {"Hz", 0.1, 1000.0, "mapper task rate"});
    v.field("iterations_per_tick", iterations_per_tick,
            {"iterations", 1, 1000, "optimisation iterations per mapper tick when budget_ms is 0"});
    v.field("budget_ms", budget_ms,
            {"ms", 0.0, 10000.0,
             "mapper time per tick (insertion + iterations); an iteration starts only while time "
             "is left, an overrun is taken from the next tick; 0 = iterations_per_tick"});
    v.field("window_keyframes", window_keyframes,
            {"keyframes", 1, 1000, "recent keyframes trained in turn"});
    v.field("random_keyframes", random_keyframes,
            {"keyframes", 0, 1000, "older keyframes drawn at random per round"});
  }
};

}  // namespace vigs::config
