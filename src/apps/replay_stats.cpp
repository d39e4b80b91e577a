#include "apps/replay_stats.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "io/mcap/damage_object.hpp"
#include "pipeline/replay_figures.hpp"
#include "pipeline/results_writer.hpp"

namespace vigs::apps {

std::string used_of(const pipeline::ReplayResult& r) {
  return std::to_string(r.frames.size()) + " frames" +
         (r.frames.empty() ? std::string()
                           : " up to t = " + std::to_string(r.frames.back().t_ns * 1e-9) + " s") +
         " and " + std::to_string(r.imu_samples) + " IMU samples";
}

io::Json stats_json(const pipeline::ReplayResult& r, const std::string& recording) {
  const pipeline::OdometryCounters& c = r.counters;
  const std::size_t n = r.frames.size();
  const double frames = static_cast<double>(n);
  const auto num = [](double v) { return io::rounded(v, 10); };
  io::Json s;
  s["recording"] = recording;
  s["guess"] = std::string(pipeline::to_string(r.guess));
  s["fusion"] = std::string(
      r.guess == tracking::InitialGuessMode::imu ? pipeline::to_string(r.fusion) : "none");
  s["initial_pose"] = std::string(pipeline::to_string(r.initial_pose));
  s["frames"] = n;
  s["wall_s"] = num(r.wall_s);
  s["fps"] = r.wall_s > 0 ? num(frames / r.wall_s) : io::Json(nullptr);
  s["track_ms_per_frame"] = n > 0 ? num(1e3 * r.track_s / frames) : io::Json(nullptr);
  s["peak_rss_bytes"] = std::llround(pipeline::peak_rss_bytes());
  const auto or_null = [&num](std::optional<double> v) { return v ? num(*v) : io::Json(nullptr); };
  s["track_ms_p50"] = or_null(pipeline::track_ms_quantile(r, 0.5));
  s["track_ms_p99"] = or_null(pipeline::track_ms_quantile(r, 0.99));
  s["gicp_iterations_mean"] = or_null(pipeline::mean_gicp_iterations(r));
  s["tracked"] = c.tracked;
  s["not_converged"] = c.not_converged;
  s["degenerate"] = c.degenerate;
  s["moving_points"] = c.moving_points;
  s["fused_updates"] = c.fused_updates;
  s["zero_velocity_updates"] = c.zero_velocity_updates;
  s["zupt_gated"] = c.zupt_gated;
  s["lost"] = c.lost;
  s["lost_low_inliers"] = c.lost_low_inliers;
  s["lost_diverged"] = c.lost_diverged;
  s["lost_degenerate"] = c.lost_degenerate;
  s["keyframes"] = c.keyframes;
  s["reinitializations"] = c.reinitializations;
  s["imu_guesses"] = c.imu_guesses;
  s["imu_unavailable"] = c.imu_unavailable;
  s["imu_resets"] = c.imu_resets;
  s["imu_samples"] = r.imu_samples;
  s["imu_samples_fed"] = r.imu_samples_fed;
  s["frames_without_depth"] = r.frames_without_depth;
  s["frames_not_tracked_by_run"] = r.frames_not_tracked_by_run;
  s["frames_skipped_at_start"] = r.frames_skipped_at_start;
  s["input_damage"] = io::mcap::damage_object(r.damage, used_of(r));
  if (r.loop) {
    const tracking::LoopClosureStats& l = *r.loop;
    s["loop_closure"] = {{"keyframes", l.keyframes},
                         {"anchors", l.anchors},
                         {"anchors_dropped", l.anchors_dropped},
                         {"anchor_bytes", l.anchor_bytes},
                         {"attempts", l.attempts},
                         {"closures", l.closures},
                         {"rejected", l.rejected},
                         {"graph_iterations", l.last_optimization.iterations},
                         {"graph_initial_cost", num(l.last_optimization.initial_cost)},
                         {"graph_final_cost", num(l.last_optimization.final_cost)}};
  }
  if (r.map) {
    s["gaussians"] = r.map->size();
    // Where the keyframes went into the map: `vigs eval run` renders at the same poses.
    s["map_poses"] = std::string(pipeline::to_string(r.map_poses));
    s["map_iterations"] = r.map_iterations;
    s["map_coarse_iterations"] = r.map_coarse_iterations;
    s["map_ms_per_frame"] = n > 0 ? num(1e3 * r.map_s / frames) : io::Json(nullptr);
    s["map_budget_ms"] = r.map_budget_ms > 0 ? num(r.map_budget_ms) : io::Json(nullptr);
    s["map_budget_overruns"] = r.map_budget_overruns;
    s["map_bytes_per_gaussian"] = num(r.map_bytes_per_gaussian);
    const mapping::MapperMemory& m = r.map_memory;
    s["map_memory_bytes"] = m.total_bytes();
    s["map_memory_by_owner_bytes"] = {{"map_params", m.map_params_bytes},
                                      {"adam_moments", m.adam_moments_bytes},
                                      {"optimizer_buffers", m.optimizer_buffers_bytes},
                                      {"occupancy", m.occupancy_bytes},
                                      {"see_through", m.see_through_bytes},
                                      {"keyframes", m.keyframes_bytes},
                                      {"snapshot", m.snapshot_bytes},
                                      {"view_buffers", m.view_buffers_bytes}};
    s["map_gated_points"] = r.map_gated_points;
    s["map_seen_through_pruned"] = r.map_seen_through_pruned;
    s["map_refined_closer"] = r.map_refined_closer;
    s["map_nonfinite_gradients"] = r.map_nonfinite_gradients;
    s["map_moved_by_loops"] = r.map_moved_by_loops;
  }
  return s;
}

}  // namespace vigs::apps
