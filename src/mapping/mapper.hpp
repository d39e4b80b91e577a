#pragma once
// The mapper task's body: ingest keyframes from the tracker's ring, insert their Gaussians and
// run optimisation iterations, newest keyframe first, then rounds over a window of recent
// keyframes plus a few random older ones. tick() is what the fixed-rate rt::PeriodicTask calls.
//
// Keyframe queue policy (see rt/spsc_ring.hpp): at most `max_pending` unprocessed keyframes are
// kept; older extra ones are skipped and counted (skipped_keyframes). A keyframe with
// end_of_stream set ends the stream; the mapper then keeps optimising until stopped.
// Snapshots: request_snapshot() (any thread) asks for a copy; the mapper publishes it at the end
// of its next tick through an atomic shared pointer, so an exporter never holds anything the
// mapper waits for.
#include <atomic>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "core/config/mapping_settings.hpp"
#include "mapping/insertion.hpp"
#include "mapping/map_optimizer.hpp"
#include "rt/counters.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::mapping {

/// What the tracker hands the mapper per keyframe: Gaussians to insert and the training view.
struct MapperKeyframe {
  std::uint64_t id = 0;
  KeyframeGaussians gaussians;
  RenderCamera camera;         ///< intrinsics and pose of the view
  std::vector<float> rgb;      ///< 3 per pixel, [0, 1]
  std::vector<float> depth_m;  ///< 1 per pixel, 0 = missing
  bool end_of_stream = false;
};
using KeyframeRing = rt::SpscRing<std::unique_ptr<MapperKeyframe>>;

class Mapper {
 public:
  /// `ring` is consumed only from tick(). `pool` may be null.
  Mapper(const config::MappingSettings& s, KeyframeRing& ring, rt::WorkerTeam* pool,
         std::size_t max_pending = 4, std::size_t max_keyframes = 32);

  /// One mapper cycle: drain the ring, insert, iterations_per_tick iterations, publish a
  /// snapshot when one was requested.
  void tick();

  void request_snapshot() noexcept { snapshot_requested_.store(true, std::memory_order_release); }
  /// The latest published snapshot (null before the first); any thread.
  [[nodiscard]] std::shared_ptr<const GaussianMap> snapshot() const {
    return snapshot_.load(std::memory_order_acquire);
  }

  [[nodiscard]] const GaussianMap& map() const { return map_; }  ///< mapper thread only
  [[nodiscard]] bool end_of_stream() const noexcept { return eos_.load(); }
  [[nodiscard]] std::uint64_t keyframes_ingested() const noexcept { return ingested_.get(); }
  [[nodiscard]] std::uint64_t skipped_keyframes() const noexcept { return skipped_.get(); }
  [[nodiscard]] std::uint64_t iterations() const noexcept { return iterations_.get(); }
  [[nodiscard]] std::uint64_t last_trained_id() const noexcept { return last_id_.load(); }
  [[nodiscard]] float last_loss() const noexcept { return last_loss_.load(); }

 private:
  std::size_t next_view();

  config::MappingSettings s_;
  KeyframeRing& ring_;
  std::size_t max_pending_, max_keyframes_;
  GaussianMap map_;
  GaussianInserter inserter_;
  MapOptimizer optimizer_;
  std::vector<std::unique_ptr<MapperKeyframe>> keyframes_;  ///< oldest first
  std::vector<std::size_t> round_;                          ///< indices still to train this round
  bool newest_pending_ = false;
  std::mt19937 rng_{12345};
  std::atomic<bool> snapshot_requested_{false};
  std::atomic<std::shared_ptr<const GaussianMap>> snapshot_;
  std::atomic<bool> eos_{false};
  std::atomic<std::uint64_t> last_id_{0};
  std::atomic<float> last_loss_{0.0f};
  rt::SingleWriterCounter ingested_, skipped_, iterations_;
};

}  // namespace vigs::mapping
