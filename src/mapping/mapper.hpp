#pragma once
// The mapper task's body: ingest keyframes from the tracker's ring, insert their Gaussians and
// run optimisation iterations, newest keyframe first, then rounds of a few random older
// keyframes followed by a window of recent ones, newest first. tick() is what the fixed-rate
// rt::PeriodicTask calls.
//
// Time budget (mapping.budget_ms > 0): a tick's insertion and iterations share the budget; an
// iteration starts only while time is left, so a tick overruns by less than one iteration (plus
// insertion), and an overrun is taken from the next tick's budget, so the average stays within
// it. With budget_ms 0 a tick runs iterations_per_tick iterations. A budgeted replay is not
// deterministic (the iteration count follows the wall clock).
//
// Insertion: a keyframe's points are first gated against a render of the map from the
// keyframe's camera (insertion_gate.hpp: only where the map is missing or wrong; at half
// resolution with mapping.gate_half_res), then inserted;
// pixels without depth where that render is empty get far Gaussians (far_field.hpp). Before
// that, the keyframe votes on every Gaussian of the map, and those it and earlier keyframes saw
// through are pruned (see_through.hpp, mapping.see_through_*), and those it sees from much
// closer than their size stands for are replaced (closer_refine.hpp, mapping.refine_closer_ratio),
// so that the keyframe fills what they leave. A keyframe's depth may mark pixels of
// moving objects with -1 (pipeline/moving_pixels.hpp): neither loss nor far field nor the vote
// uses them.
//
// Coarse iterations (mapping.coarse_iterations = N > 0): a keyframe's first N training
// iterations render its half-resolution view (half_res_view.hpp), made once at ingestion; the
// later ones render the full view.
//
// Keyframe queue policy (see rt/spsc_ring.hpp): at most `max_pending` unprocessed keyframes are
// kept; older extra ones are skipped and counted (skipped_keyframes). A keyframe with
// end_of_stream set ends the stream; the mapper then keeps optimising until stopped.
// Loop closure: every Gaussian remembers the keyframe that inserted it (its id), and
// move_keyframes() moves each keyframe's Gaussians and training view with a correction of its
// pose (keyframe_correction.hpp), so that the map follows the loop closer's solved trajectory.
// Snapshots: request_snapshot() (any thread) asks for a copy; the mapper publishes it at the end
// of its next tick through an atomic shared pointer, so an exporter never holds anything the
// mapper waits for.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <random>
#include <vector>

#include "core/config/mapping_settings.hpp"
#include "mapping/closer_refine.hpp"
#include "mapping/far_field.hpp"
#include "mapping/half_res_view.hpp"
#include "mapping/insertion.hpp"
#include "mapping/insertion_gate.hpp"
#include "mapping/keyframe_correction.hpp"
#include "mapping/map_optimizer.hpp"
#include "mapping/mapper_memory.hpp"
#include "mapping/see_through.hpp"
#include "rt/counters.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::mapping {

/// What the tracker hands the mapper per keyframe: Gaussians to insert and the training view.
struct MapperKeyframe {
  std::uint64_t id = 0;
  KeyframeGaussians gaussians;
  RenderCamera camera;         ///< intrinsics and pose of the view
  std::vector<float> rgb;      ///< 3 per pixel, [0, 1]
  std::vector<float> depth_m;  ///< 1 per pixel, 0 = missing, < 0 = moving (masked)
  bool end_of_stream = false;
  /// Filled by the Mapper at ingestion when mapping.coarse_iterations > 0.
  HalfResView half;
  int trained = 0;  ///< training iterations this keyframe has had (mapper thread)
};
using KeyframeRing = rt::SpscRing<std::unique_ptr<MapperKeyframe>>;

class Mapper {
 public:
  /// `ring` is consumed only from tick(). `pool` may be null. The mapper holds the views of the
  /// last `max_keyframes` keyframes for training (the oldest is dropped): 96 trained no better
  /// than 32 on the 3-minute office, at three times the views' memory (BENCHMARKS.md, #12).
  Mapper(const config::MappingSettings& s, KeyframeRing& ring, rt::WorkerTeam* pool,
         std::size_t max_pending = 4, std::size_t max_keyframes = 32);

  /// One mapper cycle: drain the ring, insert, iterations_per_tick iterations (or as many as
  /// the budget allows), publish a snapshot when one was requested.
  void tick();

  /// Replaces the clock the budget is measured with (default rt::monotonic_ns); for tests on a
  /// simulated clock. Not while tick() runs.
  void set_clock(std::function<std::int64_t()> now_ns) { now_ns_ = std::move(now_ns); }

  void request_snapshot() noexcept { snapshot_requested_.store(true, std::memory_order_release); }
  /// The latest published snapshot (null before the first); any thread.
  [[nodiscard]] std::shared_ptr<const GaussianMap> snapshot() const {
    return snapshot_.load(std::memory_order_acquire);
  }

  [[nodiscard]] const GaussianMap& map() const { return map_; }  ///< mapper thread only
  /// The id of the keyframe that inserted each Gaussian of map(); mapper thread only.
  [[nodiscard]] const std::vector<std::uint32_t>& anchors() const { return anchor_; }
  /// Per Gaussian of map(): 1 for the far field's Gaussians, 0 for the others; mapper thread
  /// only.
  [[nodiscard]] const std::vector<std::uint8_t>& far_flags() const { return far_flag_; }

  /// Moves the Gaussians each listed keyframe inserted, and its training view if still held,
  /// by the keyframe's correction (ids unique). Mapper thread only (between ticks), or after
  /// it stopped. Returns the Gaussians moved.
  std::size_t move_keyframes(const std::vector<KeyframeCorrection>& corrections);
  /// Bytes held by the mapper, by owner (mapper_memory.hpp); mapper thread only (or after it
  /// stopped).
  [[nodiscard]] MapperMemory memory() const;
  /// memory().bytes_per_gaussian(): the owners that grow per Gaussian (map, Adam moments,
  /// rasterizer caches, occupancy, see-through counts) over the map size; mapper thread only.
  [[nodiscard]] double bytes_per_gaussian() const { return memory().bytes_per_gaussian(); }
  [[nodiscard]] bool end_of_stream() const noexcept { return eos_.load(); }
  [[nodiscard]] std::uint64_t keyframes_ingested() const noexcept { return ingested_.get(); }
  [[nodiscard]] std::uint64_t skipped_keyframes() const noexcept { return skipped_.get(); }
  [[nodiscard]] std::uint64_t iterations() const noexcept { return iterations_.get(); }
  /// Of iterations(): those rendered at half resolution (mapping.coarse_iterations).
  [[nodiscard]] std::uint64_t coarse_iterations() const noexcept { return coarse_.get(); }
  [[nodiscard]] std::uint64_t last_trained_id() const noexcept { return last_id_.load(); }
  [[nodiscard]] float last_loss() const noexcept { return last_loss_.load(); }
  /// Duration of the last tick on the mapper's clock, ns.
  [[nodiscard]] std::int64_t last_tick_ns() const noexcept { return last_tick_ns_.load(); }
  /// Ticks that ended past their (carried) budget.
  [[nodiscard]] std::uint64_t budget_overruns() const noexcept { return overruns_.get(); }
  /// Keyframe points not inserted because the map already rendered them (insertion_gate.hpp).
  [[nodiscard]] std::uint64_t gated_points() const noexcept { return gated_.get(); }
  /// Far-field Gaussians inserted (far_field.hpp).
  [[nodiscard]] std::uint64_t far_gaussians() const noexcept { return far_.get(); }
  /// Gaussians pruned because keyframes saw through them (see_through.hpp).
  [[nodiscard]] std::uint64_t seen_through_pruned() const noexcept {
    return seen_through_pruned_.get();
  }
  /// Gaussians replaced because a keyframe saw them from closer (closer_refine.hpp).
  [[nodiscard]] std::uint64_t refined_closer() const noexcept { return refined_closer_.get(); }
  /// Gaussian gradients with a non-finite entry, not applied (MapOptimizer::iterate).
  [[nodiscard]] std::uint64_t nonfinite_gradients() const noexcept {
    return optimizer_.nonfinite_gradients();
  }
  /// Gaussians moved by move_keyframes() (a Gaussian moved by two closures counts twice).
  [[nodiscard]] std::uint64_t moved_by_corrections() const noexcept { return moved_.get(); }

 private:
  std::size_t next_view();
  void iterate_once();
  /// Far Gaussians of `kf` where it has no depth, gated by gate_render_ when `rendered`.
  void insert_far_field(const MapperKeyframe& kf, bool rendered);
  /// The keyframe's see-through votes; prunes what they condemn.
  void prune_seen_through(const MapperKeyframe& kf);
  /// Removes what the keyframe sees from much closer than it was inserted for.
  void refine_closer(const MapperKeyframe& kf);
  /// Marks the Gaussians with keep[i] == 0 removed and frees their voxels.
  void mark_removed(const std::vector<char>& keep);
  /// After the optimiser pruned: the occupancy and the see-through counts follow the map.
  void after_prune();
  [[nodiscard]] bool keep_iterating(int done, std::int64_t t0_ns, std::int64_t allowance_ns);

  config::MappingSettings s_;
  KeyframeRing& ring_;
  std::size_t max_pending_, max_keyframes_;
  GaussianMap map_;
  std::vector<std::uint32_t> anchor_;   ///< per Gaussian: MapperKeyframe::id that inserted it
  std::vector<std::uint8_t> far_flag_;  ///< per Gaussian: 1 for the far field's (far_field.hpp)
  GaussianInserter inserter_;
  MapOptimizer optimizer_;
  std::vector<std::unique_ptr<MapperKeyframe>> keyframes_;  ///< oldest first
  std::vector<std::size_t> round_;                          ///< indices still to train this round
  bool newest_pending_ = false;
  bool newest_trained_ = false;  ///< the newest keyframe was the last one trained
  std::mt19937 rng_{12345};
  std::atomic<bool> snapshot_requested_{false};
  std::atomic<std::shared_ptr<const GaussianMap>> snapshot_;
  std::atomic<bool> eos_{false};
  std::atomic<std::uint64_t> last_id_{0};
  std::atomic<float> last_loss_{0.0f};
  std::atomic<std::int64_t> last_tick_ns_{0};
  std::function<std::int64_t()> now_ns_;
  std::int64_t budget_ns_ = 0;
  GateSettings gate_;
  RenderResult<float> gate_render_;
  std::vector<char> gate_keep_;
  SeeThrough seen_through_;
  std::vector<char> removal_keep_;  ///< see-through votes and closer refinement: 0 = remove
  std::int64_t carry_ns_ = 0;       ///< <= 0: overrun still to be taken from the next ticks
  rt::SingleWriterCounter ingested_, skipped_, iterations_, coarse_, overruns_, gated_, far_,
      seen_through_pruned_, refined_closer_, moved_;
};

}  // namespace vigs::mapping
