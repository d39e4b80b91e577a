#include "mapping/mapper.hpp"

#include <algorithm>

#include "core/capacity_bytes.hpp"
#include "core/grow_by_eighths.hpp"
#include "mapping/compact_kept.hpp"
#include "rt/clock.hpp"
#include "rt/queue_policy.hpp"

namespace vigs::mapping {

Mapper::Mapper(const config::MappingSettings& s, KeyframeRing& ring, rt::WorkerTeam* pool,
               std::size_t max_pending, std::size_t max_keyframes)
    : s_(s),
      ring_(ring),
      max_pending_(max_pending),
      max_keyframes_(std::max<std::size_t>(1, max_keyframes)),
      inserter_(s.insert),
      optimizer_(s, pool),
      now_ns_(&rt::monotonic_ns),
      budget_ns_(static_cast<std::int64_t>(s.budget_ms * 1e6 + 0.5)),
      seen_through_(s.see_through) {}

std::size_t Mapper::next_view() {
  const std::size_t n = keyframes_.size();
  if (newest_pending_) {
    newest_pending_ = false;
    newest_trained_ = true;
    round_.clear();  // a new round starts after the newest keyframe
    return n - 1;
  }
  if (round_.empty()) {
    // Trained back to front: random older keyframes first, then the window newest first. A
    // keyframe arrives every four to seven iterations in real time and clears the round, so what
    // a round holds last is seldom reached: with the older keyframes last, no keyframe was
    // trained again once it had left the window. The newest keyframe, just trained on its
    // arrival, is left out of the round that follows (it was trained twice in a row).
    // BENCHMARKS.md, the twenty-fifth session.
    const std::size_t window =
        std::min<std::size_t>(n, static_cast<std::size_t>(s_.window_keyframes));
    const std::size_t older = n - window;
    const std::size_t in_round = newest_trained_ ? window - 1 : window;
    for (std::size_t k = 0; k < in_round; ++k) round_.push_back(older + k);
    for (int r = 0; r < s_.random_keyframes && older > 0; ++r)
      round_.push_back(std::uniform_int_distribution<std::size_t>(0, older - 1)(rng_));
    if (round_.empty()) round_.push_back(n - 1);  // the only keyframe
    newest_trained_ = false;
  }
  const std::size_t idx = round_.back();
  round_.pop_back();
  return idx;
}

void Mapper::iterate_once() {
  MapperKeyframe& kf = *keyframes_[next_view()];
  const bool coarse = kf.trained < s_.coarse_iterations && !kf.half.rgb.empty();
  const TrainingView view =
      coarse ? TrainingView{kf.half.camera, kf.half.rgb.data(),
                            kf.half.depth_m.empty() ? nullptr : kf.half.depth_m.data()}
             : TrainingView{kf.camera, kf.rgb.data(),
                            kf.depth_m.empty() ? nullptr : kf.depth_m.data()};
  ++kf.trained;
  if (coarse) coarse_.add(1);
  std::size_t pruned = 0;
  const auto terms = optimizer_.iterate(map_, view, &pruned,
                                        s_.far_field.fixed_geometry ? far_flag_.data() : nullptr);
  if (pruned > 0) after_prune();
  last_id_.store(kf.id);
  last_loss_.store(terms.total);
  iterations_.add(1);
}

bool Mapper::keep_iterating(int done, std::int64_t t0_ns, std::int64_t allowance_ns) {
  if (budget_ns_ <= 0) return done < s_.iterations_per_tick;
  return now_ns_() - t0_ns < allowance_ns;
}

void Mapper::tick() {
  const std::int64_t t0_ns = now_ns_();
  const std::int64_t allowance_ns = budget_ns_ + carry_ns_;
  // keyframes beyond the bound are skipped (oldest first) and counted
  rt::trim_oldest(ring_, max_pending_, skipped_);
  while (std::unique_ptr<MapperKeyframe>* front = ring_.front()) {
    std::unique_ptr<MapperKeyframe> kf = std::move(*front);
    ring_.pop();
    if (!kf) continue;
    if (kf->end_of_stream) {
      eos_.store(true);
      continue;
    }
    // see-through votes first: what they prune leaves room that this keyframe's points and far
    // field fill at once (the gate's render below no longer shows it)
    prune_seen_through(*kf);
    refine_closer(*kf);
    const std::vector<char>* keep = nullptr;
    if (map_.size() > 0 && kf->camera.width_px > 0) {
      const RenderCamera gate_camera = s_.gate_half_res ? half_res_camera(kf->camera) : kf->camera;
      optimizer_.rasterizer().forward(map_, gate_camera, gate_render_, optimizer_.blocks());
      const std::size_t kept =
          gate_points(kf->gaussians, gate_camera, gate_render_, gate_, gate_keep_);
      gated_.add(kf->gaussians.points_c.size() - kept);
      keep = &gate_keep_;
    }
    const std::size_t first_new = map_.size();
    inserter_.insert(map_, kf->gaussians, keep);
    const std::size_t first_far = map_.size();
    insert_far_field(*kf, keep != nullptr);
    resize_by_eighths(anchor_, map_.size());  // capacity as the map's arrays grow
    std::fill(anchor_.begin() + static_cast<std::ptrdiff_t>(first_new), anchor_.end(),
              static_cast<std::uint32_t>(kf->id));
    resize_by_eighths(far_flag_, map_.size());
    std::fill(far_flag_.begin() + static_cast<std::ptrdiff_t>(first_new),
              far_flag_.begin() + static_cast<std::ptrdiff_t>(first_far), std::uint8_t{0});
    std::fill(far_flag_.begin() + static_cast<std::ptrdiff_t>(first_far), far_flag_.end(),
              std::uint8_t{1});
    kf->gaussians = KeyframeGaussians{};  // points are in the map now; keep only the view
    if (s_.coarse_iterations > 0 && kf->camera.width_px >= 2 && !kf->rgb.empty())
      make_half_res_view(kf->camera, kf->rgb.data(),
                         kf->depth_m.empty() ? nullptr : kf->depth_m.data(), kf->half);
    if (keyframes_.size() == max_keyframes_) keyframes_.erase(keyframes_.begin());
    keyframes_.push_back(std::move(kf));
    round_.clear();
    newest_pending_ = true;
    ingested_.add(1);
  }
  if (!keyframes_.empty()) {
    for (int done = 0; keep_iterating(done, t0_ns, allowance_ns); ++done) iterate_once();
  }
  if (snapshot_requested_.exchange(false, std::memory_order_acq_rel))
    snapshot_.store(std::make_shared<const GaussianMap>(map_), std::memory_order_release);
  const std::int64_t spent_ns = now_ns_() - t0_ns;
  last_tick_ns_.store(spent_ns);
  if (budget_ns_ > 0) {
    // an overrun is paid back by the following ticks (it is under one iteration plus the
    // insertion, since an iteration starts only while time is left); unused time is not saved
    carry_ns_ = std::min<std::int64_t>(allowance_ns - spent_ns, 0);
    if (spent_ns > allowance_ns) overruns_.add(1);
  }
}

void Mapper::insert_far_field(const MapperKeyframe& kf, bool rendered) {
  if (kf.camera.width_px <= 0 || kf.rgb.empty()) return;
  const FarFieldView view{kf.camera, kf.rgb.data(),
                          kf.depth_m.empty() ? nullptr : kf.depth_m.data()};
  far_.add(mapping::insert_far_field(map_, view, rendered ? &gate_render_ : nullptr, s_.far_field,
                                     s_.insert.cover, s_.insert.opacity, gate_.max_alpha,
                                     0.9 * s_.prune.max_scale_m));
}

}  // namespace vigs::mapping

namespace vigs::mapping {

void Mapper::after_prune() {
  inserter_.rebuild(map_);
  const std::vector<char>& keep = optimizer_.last_prune_keep();
  compact_kept(anchor_, keep);
  compact_kept(far_flag_, keep);
  if (s_.see_through.enabled) seen_through_.compact(keep);
}

void Mapper::prune_seen_through(const MapperKeyframe& kf) {
  if (!s_.see_through.enabled || kf.depth_m.empty() || kf.camera.width_px <= 0) return;
  const std::size_t condemned = seen_through_.vote(
      map_, kf.camera, kf.depth_m.data(), removal_keep_, optimizer_.blocks(),
      anchor_.size() == map_.size() ? anchor_.data() : nullptr, static_cast<std::uint32_t>(kf.id),
      far_flag_.size() == map_.size() ? far_flag_.data() : nullptr);
  if (condemned == 0) return;
  mark_removed(removal_keep_);
  seen_through_pruned_.add(condemned);
}

void Mapper::refine_closer(const MapperKeyframe& kf) {
  if (!(s_.closer_refine.ratio > 0.0) || kf.depth_m.empty() || kf.camera.width_px <= 0) return;
  const std::size_t condemned =
      condemn_seen_closer(map_, kf.camera, kf.depth_m.data(), kf.gaussians.sample_angle_rad,
                          s_.insert, s_.closer_refine, removal_keep_, optimizer_.blocks());
  if (condemned == 0) return;
  mark_removed(removal_keep_);
  refined_closer_.add(condemned);
}

void Mapper::mark_removed(const std::vector<char>& keep) {
  inserter_.forget(map_, keep);  // not a rebuild: that is O(map) per keyframe
  // Marked removed, not compacted: they leave the render at once, and the optimiser's next
  // prune compacts them out with the map's other thin Gaussians (after_prune() then compacts
  // the see-through counts), instead of an O(map) compaction per keyframe.
  for (std::size_t i = 0; i < keep.size(); ++i)
    if (!keep[i]) map_.opacity_logit[i] = kRemovedLogit;
}

std::size_t Mapper::move_keyframes(const std::vector<KeyframeCorrection>& corrections) {
  if (corrections.empty()) return 0;
  const std::size_t moved = move_anchored(map_, anchor_, corrections);
  for (const auto& kf : keyframes_) {
    for (const KeyframeCorrection& c : corrections) {
      if (c.id != kf->id) continue;
      move_camera(kf->camera, c.T_new_old);
      move_camera(kf->half.camera, c.T_new_old);
    }
  }
  // The block bounds follow at once. The insertion occupancy follows at the next prune's
  // rebuild (every mapping.prune_every iterations): rebuilding two million voxels at every
  // closure, or at every closure that moved a Gaussian by half a voxel (most do), held the
  // live mapper long enough to drop keyframes at its queue (42-53 of 590 over three minutes,
  // against 14 without and 20 without the moves); until then the insertion gate, which
  // renders the moved map, keeps a keyframe from inserting again what moved. Adam's moments
  // stay: a rigid motion of a few centimetres leaves their scale as it was.
  if (MapBlocks* b = optimizer_.blocks()) b->invalidate();
  moved_.add(moved);
  return moved;
}

MapperMemory Mapper::memory() const {
  MapperMemory m;
  m.gaussians = map_.size();
  m.map_params_bytes = map_.capacity_bytes() + capacity_bytes(anchor_) + capacity_bytes(far_flag_);
  m.adam_moments_bytes = optimizer_.moment_bytes();
  m.optimizer_buffers_bytes = optimizer_.buffer_bytes();
  m.occupancy_bytes = inserter_.occupancy_bytes();
  m.see_through_bytes = seen_through_.bytes() + capacity_bytes(removal_keep_);
  m.keyframes_bytes = capacity_bytes(keyframes_) + capacity_bytes(round_);
  for (const auto& kf : keyframes_) {
    const KeyframeGaussians& g = kf->gaussians;
    m.keyframes_bytes += sizeof(MapperKeyframe) + capacity_bytes(kf->rgb) +
                         capacity_bytes(kf->depth_m) + capacity_bytes(kf->half.rgb) +
                         capacity_bytes(kf->half.depth_m) + capacity_bytes(g.points_c) +
                         capacity_bytes(g.covariances_c) + capacity_bytes(g.colors);
  }
  if (const std::shared_ptr<const GaussianMap> snap = snapshot())
    m.snapshot_bytes = snap->capacity_bytes();
  m.view_buffers_bytes =
      optimizer_.view_bytes() + gate_render_.capacity_bytes() + capacity_bytes(gate_keep_);
  return m;
}

}  // namespace vigs::mapping
