#pragma once
#include "core/config/mapping_components.hpp"
#include "core/config/visitor.hpp"

namespace vigs::config {

/// Gaussian-splatting map: loss weights, Adam learning rates (GS-ICP SLAM's but for the means),
/// pruning, insertion, the far field, people out of the map (moving mask, see-through pruning) and
/// the mapper task's schedule. The components' parts (loss, adam, prune, insert, far_field,
/// see_through, closer_refine, moving_mask) are declared with their defaults in
/// mapping_components.hpp; their docs are here.
struct MappingSettings {
  LossSettings loss;
  AdamSettings adam;
  int prune_every = 50;
  PruneSettings prune;
  InsertSettings insert;
  FarFieldSettings far_field;
  SeeThroughSettings see_through;
  CloserRefineSettings closer_refine;
  MovingMaskSettings moving_mask;
  int threads = 2;
  double rate_hz = 200.0;  ///< a busy mapper's ticks are longer: back to back
  int iterations_per_tick = 1;
  int coarse_iterations = 8;  ///< mapping/half_res_view.hpp
  bool gate_half_res = true;  ///< the insertion gate's render at half resolution
  double budget_ms = 0.0;     ///< > 0 replaces iterations_per_tick
  int window_keyframes = 8;
  bool block_culling = true;  ///< mapping/map_blocks.hpp
  int random_keyframes = 2;
  bool follow_loop_closures = true;  ///< pipeline/map_loop_correction.hpp

  void visit(Visitor& v) {
    v.field("lambda_ssim", loss.lambda_ssim, {"-", 0.0, 1.0, "weight of (1 - SSIM) against L1"});
    v.field("lambda_depth", loss.lambda_depth, {"1/m", 0.0, 100.0, "weight of the depth L1 term"});
    v.field("lr_mean", adam.lr_mean, {"m", 0.0, 1.0, "Adam step size of positions"});
    v.field("lr_log_scale", adam.lr_log_scale, {"-", 0.0, 1.0, "Adam step size of log-scales"});
    v.field("lr_quat", adam.lr_quat, {"-", 0.0, 1.0, "Adam step size of quaternions"});
    v.field("lr_opacity", adam.lr_opacity, {"-", 0.0, 1.0, "Adam step size of opacity logits"});
    v.field("lr_color", adam.lr_color, {"-", 0.0, 1.0, "Adam step size of RGB colour"});
    v.field("adam_visible_only", adam.visible_only,
            "Adam steps only the Gaussians the iteration's view sees (gsplat's selective Adam): "
            "an iteration costs what the view sees, not the map, and a Gaussian's moments are "
            "decayed over the steps it skipped before its next step; off: every Gaussian moves "
            "by its momentum each iteration");
    v.field("block_culling", block_culling,
            "skip whole blocks of 1024 Gaussians that a view cannot see before projecting, in "
            "every render and the see-through vote (the result is the same; off: every "
            "Gaussian of the map is projected, the baseline it is measured against)");
    v.field("prune_every", prune_every, {"iterations", 1, 100000, "pruning period"});
    v.field("prune_min_opacity", prune.min_opacity,
            {"-", 0.0, 1.0, "Gaussians below this opacity are pruned"});
    v.field("prune_max_scale_m", prune.max_scale_m,
            {"m", 0.001, 100.0, "Gaussians with a larger standard deviation are pruned"});
    v.field("insert_voxel_m", insert.voxel_m,
            {"m", 0.001, 1.0, "insertion skips voxels of this size that already hold a Gaussian"});
    v.field("insert_opacity", insert.opacity,
            {"-", 0.001, 0.99,
             "opacity of new Gaussians at full depth confidence (lower where the sample's "
             "covariance is thick against its footprint); the flat opacity without a sample "
             "angle"});
    v.field("min_scale_m", insert.min_scale_m,
            {"m", 1e-6, 1.0, "floor on initial standard deviations"});
    v.field("far_field_depth_m", far_field.depth_m,
            {"m", 0.0, 1000.0,
             "camera depth at which pixels without depth get far Gaussians (set it beyond "
             "camera.max_depth_m); 0 = no far field"});
    v.field("far_field_stride_px", far_field.stride_px,
            {"px", 1, 256, "one far Gaussian per stride x stride pixel block without depth"});
    v.field("far_field_fixed_geometry", far_field.fixed_geometry,
            "far Gaussians keep the mean, scale and rotation insertion gave them (their depth "
            "stands for 'beyond the range'); training changes only their colour and opacity; "
            "off: all of their parameters are trained");
    v.field("see_through_enabled", see_through.enabled,
            "prune Gaussians that later keyframes see through (a surface measured behind them: "
            "a person who stood there only for a moment)");
    v.field("see_through_margin_m", see_through.margin_m,
            {"m", 0.0, 10.0,
             "a keyframe sees through a Gaussian when its measured depth at the Gaussian's pixel "
             "lies behind it by more than this plus see_through_margin_per_m times its depth"});
    v.field("see_through_margin_per_m", see_through.margin_per_m,
            {"m/m", 0.0, 1.0, "growth of the see-through margin with the Gaussian's depth"});
    v.field("see_through_min_count", see_through.min_count,
            {"keyframes", 1, 1000, "keyframes that must see through a Gaussian to prune it"});
    v.field("see_through_min_fraction", see_through.min_fraction,
            {"-", 0.0, 1.0,
             "and at least this share of the keyframes that voted on it (seen through or seen "
             "on the surface)"});
    v.field("see_through_max_age_keyframes", see_through.max_age_keyframes,
            {"keyframes", 0, 1000000,
             "only keyframes at most this many after the one that inserted a Gaussian vote on "
             "it: their poses are odometry-close, while a revisit minutes later carries the "
             "drift between (which a 10 cm margin cannot hold); 0 = every later keyframe"});
    v.field("see_through_missing_far", see_through.missing_far,
            "for the see-through vote a pixel without depth is beyond the depth range (a "
            "corridor's end, as the far field takes it); off: such pixels do not vote");
    v.field("refine_closer_ratio", closer_refine.ratio,
            {"-", 0.0, 100.0,
             "a Gaussian that a keyframe sees on its measured surface, whole, from closer than "
             "its size stands for (its in-plane standard deviation above this times the "
             "keyframe's own sample's there) is replaced by the keyframe's finer samples; 0 = "
             "off"});
    v.field("moving_mask", moving_mask.enabled,
            "pixels of the points the tracker flagged moving are neither colour nor depth "
            "targets of the keyframe's training view, nor far field");
    v.field("moving_mask_dilation_px", moving_mask.dilation_px,
            {"px", 0, 64, "the mask covers each moving point's pixel-stride block plus this"});
    v.field("threads", threads, {"threads", 1, 64, "rasterizer worker threads"});
    v.field("rate_hz", rate_hz,
            {"Hz", 0.1, 1000.0,
             "mapper task rate; a tick longer than the period is followed at once, so a mapper "
             "with keyframes runs back to back (its iterations take tens of ms) on whatever CPU "
             "the SCHED_FIFO threads leave (it is SCHED_IDLE), and one without polls every "
             "period (5 ms at the default 200 Hz)"});
    v.field("iterations_per_tick", iterations_per_tick,
            {"iterations", 1, 1000, "optimisation iterations per mapper tick when budget_ms is 0"});
    v.field("coarse_iterations", coarse_iterations,
            {"iterations", 0, 100000,
             "a keyframe's first N training iterations render at half resolution (a quarter of "
             "the pixels: 2x2 colour means, the blocks' near-surface depth); later ones at full "
             "resolution; 0 = every iteration at full resolution"});
    v.field("gate_half_res", gate_half_res,
            "the insertion gate (and the far field's) renders the map at half resolution from "
            "the keyframe's camera (a quarter of the pixels; the keyframe's points are sampled "
            "every few pixels anyway); off: at the camera's resolution");
    v.field("budget_ms", budget_ms,
            {"ms", 0.0, 10000.0,
             "mapper time per tick (insertion + iterations); an iteration starts only while time "
             "is left, an overrun is taken from the next ticks; 0 = iterations_per_tick"});
    v.field("window_keyframes", window_keyframes,
            {"keyframes", 1, 1000, "recent keyframes trained in turn"});
    v.field("random_keyframes", random_keyframes,
            {"keyframes", 0, 1000,
             "older keyframes drawn at random per round, trained first in the round (a new "
             "keyframe clears the round)"});
    v.field("follow_loop_closures", follow_loop_closures,
            "with tracking.loop_closure: keyframes go into the map at their loop-corrected "
            "poses, and each closure moves every keyframe's Gaussians and training view with "
            "its corrected pose, so the map and trajectory.tum share one frame; off: the map "
            "keeps the odometry's poses (and its drift where the route returns)");
  }
};

}  // namespace vigs::config
