#pragma once
// LiveMapper: the body of the live pipeline's `mapper` task (rt::PeriodicTask at
// mapping.rate_hz, SCHED_OTHER). Each tick takes the keyframes the tracker queued in the
// KeyframeHandoff, turns each into a mapping::MapperKeyframe (its Gaussians from the tracker's
// raw covariances, the frame as training view with the pixels of the points the tracker flagged
// moving masked out, moving_pixels.hpp; this allocates, on the mapper thread), releases
// the frame and the slot, and runs one mapping::Mapper tick of mapping.iterations_per_tick
// optimisation iterations, or as many as mapping.budget_ms allows when it is > 0 (the
// Mapper's budgeted tick). The tracker never waits for it except in lockstep, where a keyframe
// waits for a free slot. With tracking.loop_closure the keyframes also go to a LoopCloser, are
// placed in the map at their solved poses, and the map follows each closure
// (map_loop_correction.hpp, mapping.follow_loop_closures).
#include <atomic>
#include <cstdint>
#include <memory>

#include "core/config/mapping_settings.hpp"
#include "core/config/tracking_settings.hpp"
#include "core/types/pinhole_camera.hpp"
#include "mapping/mapper.hpp"
#include "pipeline/keyframe_handoff.hpp"
#include "pipeline/map_loop_correction.hpp"
#include "rt/frame_pool.hpp"
#include "rt/worker_team.hpp"
#include "tracking/loop_closure.hpp"

namespace vigs::pipeline {

class LiveMapper {
 public:
  /// `worker_spec`: the thread table's mapper_w1 with the rt policy applied.
  /// `tracker_pixel_stride`: the stride the keyframes' points were sampled at.
  /// `loops` (nullable): tracking.loop_closure on; the keyframes also go to a LoopCloser on
  /// this thread (one GICP thread, this one: it starts no thread of its own).
  LiveMapper(const config::MappingSettings& s, const PinholeCamera& camera, float depth_scale_m,
             rt::FramePool& pool, KeyframeHandoff& handoff, const rt::ThreadSpec& worker_spec,
             int tracker_pixel_stride, const config::TrackingSettings* loops = nullptr);

  /// The task body (mapper thread only).
  void tick();

  /// The tracker's end marker arrived (every keyframe is in the map).
  [[nodiscard]] bool ended() const noexcept { return ended_.load(std::memory_order_acquire); }
  /// Mapper thread, or any thread once the task stopped.
  [[nodiscard]] const mapping::Mapper& mapper() const { return *mapper_; }
  [[nodiscard]] std::int64_t busy_ns() const noexcept { return busy_ns_.load(); }
  /// Gaussians in the map after the last tick (any thread).
  [[nodiscard]] std::size_t gaussians() const noexcept { return gaussians_.load(); }
  /// The loop closer (null when off): mapper thread, or any thread once the task stopped.
  [[nodiscard]] tracking::LoopCloser* loop_closer() { return loops_.get(); }
  /// After the task stopped and the closer's graph was solved a last time: the map follows it
  /// (map_loop_correction.hpp). Returns the keyframes moved.
  std::size_t follow_loop_closures();

 private:
  PinholeCamera camera_;
  float depth_scale_m_;
  config::MovingMaskSettings moving_mask_;
  int stride_px_;
  rt::FramePool& pool_;
  KeyframeHandoff& handoff_;
  rt::WorkerTeam team_;
  mapping::KeyframeRing ring_;
  std::unique_ptr<mapping::Mapper> mapper_;
  std::unique_ptr<tracking::LoopCloser> loops_;
  MapLoopCorrection map_correction_;
  bool follow_loops_ = false;  ///< mapping.follow_loop_closures (with loops)
  std::uint64_t next_id_ = 0;
  std::atomic<bool> ended_{false};
  std::atomic<std::int64_t> busy_ns_{0};
  std::atomic<std::size_t> gaussians_{0};
};

}  // namespace vigs::pipeline
