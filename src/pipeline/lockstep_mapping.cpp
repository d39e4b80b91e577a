#include "pipeline/lockstep_mapping.hpp"

#include <algorithm>

#include "pipeline/mapper_keyframe.hpp"

namespace vigs::pipeline {
namespace {

config::MappingSettings with_schedule(config::MappingSettings s, int iterations_per_frame,
                                      double budget_ms) {
  s.iterations_per_tick = std::max(1, iterations_per_frame);
  s.budget_ms = budget_ms;  // the replay's flags choose the schedule, not the robot file
  return s;
}

}  // namespace

LockstepMapper::LockstepMapper(const config::MappingSettings& s, const PinholeCamera& camera,
                               int iterations_per_frame, double budget_ms, int tracker_pixel_stride)
    : camera_(camera),
      moving_mask_(s.moving_mask),
      stride_px_(std::max(1, tracker_pixel_stride)),
      pool_(s.threads, rt::ThreadSpec{.name = "mapper_w1"}),
      ring_(8),
      // max_pending 4: a replay adds at most one keyframe per tick, so nothing is skipped.
      mapper_(std::make_unique<mapping::Mapper>(with_schedule(s, iterations_per_frame, budget_ms),
                                                ring_, &pool_)) {}

void LockstepMapper::add_keyframe(const tracking::Keyframe& kf, const RgbdView& frame) {
  ImageU8 rgb;
  ImageF32 depth_m;
  copy_rgb8(frame, rgb);
  copy_depth_m(frame, depth_m);
  add(next_id_++, kf, rgb, std::move(depth_m), nullptr);
}

void LockstepMapper::keep_frames(int frames) {
  kept_.assign(static_cast<std::size_t>(std::max(0, frames)), KeptFrame{});
  next_kept_ = 0;
}

void LockstepMapper::keep_frame(const RgbdView& frame) {
  if (kept_.empty()) return;
  KeptFrame& k = kept_[next_kept_];
  next_kept_ = (next_kept_ + 1) % kept_.size();
  k.t_ns = frame.t_ns;
  copy_rgb8(frame, k.rgb);
  copy_depth_m(frame, k.depth_m);
}

bool LockstepMapper::add_keyframe(const tracking::Keyframe& kf, const geometry::Pose* T_w_c_map) {
  const std::uint64_t id = next_id_++;
  for (const KeptFrame& k : kept_) {
    if (k.t_ns == kf.t_ns) {
      add(id, kf, k.rgb, k.depth_m, T_w_c_map);
      return true;
    }
  }
  return false;
}

void LockstepMapper::add(std::uint64_t id, const tracking::Keyframe& kf, const ImageU8& rgb,
                         ImageF32 depth_m, const geometry::Pose* T_w_c_map) {
  auto m = make_mapper_keyframe(id, kf, camera_, stride_px_, moving_mask_, rgb, std::move(depth_m),
                                T_w_c_map);
  // The ring holds 8 and every step() drains it, so this fails only if step() is not called;
  // the keyframe is then dropped and counted, like any keyframe beyond a queue bound.
  if (!ring_.try_push(std::move(m))) ++dropped_keyframes_;
}

}  // namespace vigs::pipeline
