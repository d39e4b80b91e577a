#include "pipeline/live_mapper.hpp"

#include <algorithm>

#include "core/types/image.hpp"
#include "pipeline/mapper_keyframe.hpp"
#include "pipeline/pool_frame_view.hpp"
#include "rt/clock.hpp"

namespace vigs::pipeline {

LiveMapper::LiveMapper(const config::MappingSettings& s, const PinholeCamera& camera,
                       float depth_scale_m, rt::FramePool& pool, KeyframeHandoff& handoff,
                       const rt::ThreadSpec& worker_spec, int tracker_pixel_stride,
                       const config::TrackingSettings* loops)
    : camera_(camera),
      depth_scale_m_(depth_scale_m),
      moving_mask_(s.moving_mask),
      stride_px_(std::max(1, tracker_pixel_stride)),
      pool_(pool),
      handoff_(handoff),
      team_(s.threads, worker_spec),
      ring_(2 * handoff.capacity()),
      // max_pending = the handoff's slots: the bound is the handoff's, nothing more is skipped.
      mapper_(std::make_unique<mapping::Mapper>(s, ring_, &team_, handoff.capacity())) {
  if (loops != nullptr && loops->loop.enabled) {
    config::GicpSetting gicp = loops->gicp;
    gicp.num_threads = 1;  // on this thread only
    loops_ = std::make_unique<tracking::LoopCloser>(loops->loop, gicp);
    follow_loops_ = s.follow_loop_closures;
  }
}

void LiveMapper::tick() {
  const std::int64_t t0 = rt::monotonic_ns();
  std::uint32_t index = 0;
  bool closed = false;
  // At most one slot's worth per tick, so ring_ (twice the slots) never fills.
  for (std::size_t n = 0; n < handoff_.capacity() && !ended() && handoff_.next(index); ++n) {
    if (index == KeyframeHandoff::kEnd) {
      ended_.store(true, std::memory_order_release);
      break;
    }
    KeyframeSlot& slot = handoff_.slot(index);
    const RgbdView view =
        pool_frame_view(pool_.frame(slot.frame), pool_.settings(), depth_scale_m_);
    ImageU8 rgb;
    ImageF32 depth_m;
    copy_rgb8(view, rgb);
    copy_depth_m(view, depth_m);
    // with loops: the keyframe becomes node next_id_ of the closer's graph and goes to the map
    // at its solved pose
    geometry::Pose T_w_c_map = slot.keyframe.T_w_c;
    if (loops_) {
      closed = loops_->add_keyframe(slot.keyframe, slot.after_restart) || closed;
      if (follow_loops_) T_w_c_map = map_correction_.place(*loops_);
    }
    auto m = make_mapper_keyframe(next_id_++, slot.keyframe, camera_, stride_px_, moving_mask_, rgb,
                                  std::move(depth_m), &T_w_c_map);
    pool_.release(slot.frame);
    slot.frame = rt::FrameHandle{};
    handoff_.give_back(index);
    // The ring holds twice the slots and is drained by every Mapper::tick below.
    (void)ring_.try_push(std::move(m));
  }
  mapper_->tick();  // inserts this tick's keyframes first: a closure below moves them too
  if (closed && follow_loops_) map_correction_.apply(*loops_, *mapper_);
  gaussians_.store(mapper_->map().size(), std::memory_order_relaxed);
  busy_ns_.store(busy_ns_.load(std::memory_order_relaxed) + rt::monotonic_ns() - t0,
                 std::memory_order_relaxed);
}

std::size_t LiveMapper::follow_loop_closures() {
  return loops_ && follow_loops_ ? map_correction_.apply(*loops_, *mapper_) : 0;
}

}  // namespace vigs::pipeline
