#pragma once
// One optimisation iteration of the map against one posed RGB-D view: project, render, loss
// (L1 + SSIM + depth), backward, Adam; pruning of transparent and oversized Gaussians every N
// iterations. Gradients go straight from the rasterizer into Adam per Gaussian (no gradient copy
// of the map). Memory per Gaussian (parameters, Adam moments, rasterizer caches including the
// per-pair gradients and tile lists) is reported by bytes_per_gaussian(); the mapper's
// whole account, by owner, is Mapper::memory() (mapper_memory.hpp).
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/config/mapping_settings.hpp"
#include "mapping/adam.hpp"
#include "mapping/loss.hpp"
#include "mapping/rasterizer.hpp"

namespace vigs::mapping {

/// A training view: camera, colour (3 per pixel, [0, 1]) and depth (metres, 0 = missing).
struct TrainingView {
  RenderCamera camera;
  const float* rgb = nullptr;
  const float* depth_m = nullptr;
};

using config::PruneSettings;  // defaults: core/config/mapping_components.hpp

/// Marks Gaussians to keep: opacity >= min_opacity, every standard deviation <= max_scale_m,
/// and every parameter finite.
std::vector<char> prune_keep_mask(const GaussianMap& map, const PruneSettings& s);

class MapOptimizer {
 public:
  MapOptimizer(const config::MappingSettings& s, rt::WorkerTeam* pool);

  /// One iteration; prunes (and returns the count in `pruned`) every prune_every iterations.
  /// A Gaussian whose gradient has a non-finite entry is not stepped this iteration (counted:
  /// nonfinite_gradients()): one NaN colour renders NaN pixels, whose SSIM gradient reaches
  /// every Gaussian within its window, and so on (a lockstep replay at lambda_depth 0.03 wrote
  /// 255 NaN colours in one patch of the office, and its map.ply could not be read).
  /// With `fixed_geometry` (one per Gaussian of `map`), the Gaussians whose entry is non-zero
  /// keep their mean, scale and rotation: only their colour and opacity are trained (the far
  /// field's, mapping.far_field_fixed_geometry).
  LossTerms<float> iterate(GaussianMap& map, const TrainingView& view,
                           std::size_t* pruned = nullptr,
                           const std::uint8_t* fixed_geometry = nullptr);

  /// Removes Gaussians from the map and the optimiser state; returns the count removed. The
  /// mask it used stays readable (last_prune_keep()) for state kept beside the map.
  std::size_t prune(GaussianMap& map);
  /// Removes the Gaussians whose keep[i] is 0 from the map and the optimiser state.
  std::size_t remove(GaussianMap& map, const std::vector<char>& keep);
  /// The keep mask of the last prune() (one per Gaussian before it).
  [[nodiscard]] const std::vector<char>& last_prune_keep() const { return prune_keep_; }

  /// Bytes per Gaussian held for `map` by the map and this optimiser: (map parameters +
  /// moment_bytes() + buffer_bytes()) / size. The mapper's figure (Mapper::bytes_per_gaussian)
  /// adds the inserter's occupancy and the see-through counts.
  [[nodiscard]] double bytes_per_gaussian(const GaussianMap& map) const;
  /// Adam's moments, bytes.
  [[nodiscard]] std::size_t moment_bytes() const { return adam_.bytes(); }
  /// Rasterizer caches (Rasterizer::cache_bytes) and the prune mask, bytes.
  [[nodiscard]] std::size_t buffer_bytes() const;
  /// Per-pixel buffers: the last render and the loss's gradients, bytes.
  [[nodiscard]] std::size_t view_bytes() const;

  Rasterizer<float>& rasterizer() { return raster_; }
  PhotometricLoss<float>& loss() { return loss_; }
  /// Block bounds of the map this optimiser trains (map_blocks.hpp), kept true by iterate(),
  /// prune() and remove(); pass them to other forward passes over the same map. Null when
  /// block culling is off.
  [[nodiscard]] MapBlocks* blocks() { return use_blocks_ ? &blocks_ : nullptr; }
  /// Block culling on (the default) or off (every Gaussian projected: the baseline it is
  /// measured against; the renders are the same).
  void use_blocks(bool on) {
    use_blocks_ = on;
    blocks_.invalidate();
  }
  Adam& adam() { return adam_; }
  [[nodiscard]] long iterations() const { return iterations_; }
  /// Gaussian gradients with a non-finite entry, set to zero instead (iterate()).
  [[nodiscard]] std::uint64_t nonfinite_gradients() const {
    return nonfinite_.load(std::memory_order_relaxed);
  }
  [[nodiscard]] const RenderResult<float>& last_render() const { return render_; }

 private:
  config::MappingSettings s_;
  Rasterizer<float> raster_;
  PhotometricLoss<float> loss_;
  Adam adam_;
  RenderResult<float> render_;
  std::vector<float> v_color_, v_depth_;
  std::vector<char> prune_keep_;
  std::vector<int> dense_slot_;  ///< per Gaussian, visible slot or -1: the dense step only
  MapBlocks blocks_;
  bool use_blocks_ = true;
  long iterations_ = 0;
  std::atomic<std::uint64_t> nonfinite_{0};  ///< counted from the Adam step's threads
};

}  // namespace vigs::mapping
