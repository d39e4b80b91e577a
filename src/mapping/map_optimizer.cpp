#include "mapping/map_optimizer.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

namespace vigs::mapping {

std::vector<char> prune_keep_mask(const GaussianMap& map, const PruneSettings& s) {
  std::vector<char> keep(map.size(), 1);
  const float logit_min = static_cast<float>(std::log(s.min_opacity / (1.0 - s.min_opacity)));
  const float log_max = static_cast<float>(std::log(s.max_scale_m));
  for (std::size_t i = 0; i < map.size(); ++i) {
    const float* ls = &map.log_scale[3 * i];
    const bool too_big = std::max({ls[0], ls[1], ls[2]}) > log_max;
    const bool too_thin = map.opacity_logit[i] < logit_min;
    keep[i] = (too_big || too_thin || !map.finite(i)) ? 0 : 1;
  }
  return keep;
}

// With the far field on, every pixel has Gaussians behind it: colour is trained everywhere (the
// depth term stays masked where the target has no depth).
MapOptimizer::MapOptimizer(const config::MappingSettings& s, rt::WorkerTeam* pool)
    : s_(s),
      raster_(RasterSettings{}, pool),
      loss_(s.loss, pool, s.far_field.depth_m > 0.0),
      adam_(s.adam),
      use_blocks_(s.block_culling) {}

LossTerms<float> MapOptimizer::iterate(GaussianMap& map, const TrainingView& view,
                                       std::size_t* pruned, const std::uint8_t* fixed_geometry) {
  raster_.forward(map, view.camera, render_, blocks());
  const std::size_t np = static_cast<std::size_t>(render_.width) * render_.height;
  v_color_.resize(3 * np);
  v_depth_.resize(np);
  const LossTerms<float> terms =
      loss_.evaluate(render_, view.rgb, view.depth_m, v_color_.data(), v_depth_.data());
  raster_.accumulate_gradients(view.camera, render_, v_color_.data(),
                               view.depth_m ? v_depth_.data() : nullptr, nullptr);
  // fused: each Gaussian's gradient goes straight into its Adam update, no gradient copy
  const auto checked = [&](std::size_t i, float* g) {
    bool finite = true;
    for (int k = 0; k < Rasterizer<float>::kParamGrads; ++k) finite = finite && std::isfinite(g[k]);
    if (!finite) {
      std::fill(g, g + Rasterizer<float>::kParamGrads, 0.0f);
      nonfinite_.fetch_add(1, std::memory_order_relaxed);
    }
    // mean (3), log-scale (3), quaternion (4) first: no gradient, so Adam's moments stay zero
    // and the step is zero
    if (fixed_geometry && fixed_geometry[i]) std::fill(g, g + 10, 0.0f);
  };
  const auto ranges = [&](std::size_t n, const std::function<void(std::size_t, std::size_t)>& fn) {
    raster_.for_ranges(n, fn);
  };
  if (adam_.settings().visible_only) {
    const std::vector<int>& ids = raster_.visible_ids();
    const auto grad_of_slot = [&](std::size_t slot, float* g) {
      raster_.slot_gradient(map, view.camera, slot, g);
      checked(static_cast<std::size_t>(ids[slot]), g);
    };
    adam_.step_selected(map, ids, grad_of_slot, ranges);
    blocks_.mark_changed(ids);
  } else {
    // every Gaussian steps: each one's visible slot (the dense step is O(map) anyway)
    const std::vector<int>& ids = raster_.visible_ids();
    dense_slot_.assign(map.size(), -1);
    for (std::size_t s = 0; s < ids.size(); ++s)
      dense_slot_[static_cast<std::size_t>(ids[s])] = static_cast<int>(s);
    const auto grad_of = [&](std::size_t i, float* g) {
      if (dense_slot_[i] < 0) {
        std::fill(g, g + Rasterizer<float>::kParamGrads, 0.0f);  // culled: no gradient
      } else {
        raster_.slot_gradient(map, view.camera, static_cast<std::size_t>(dense_slot_[i]), g);
      }
      checked(i, g);
    };
    adam_.step_fused(map, grad_of, ranges);
    blocks_.invalidate();  // momentum moved Gaussians outside the view too
  }
  ++iterations_;
  std::size_t removed = 0;
  if (s_.prune_every > 0 && iterations_ % s_.prune_every == 0) removed = prune(map);
  if (pruned) *pruned = removed;
  return terms;
}

std::size_t MapOptimizer::prune(GaussianMap& map) {
  prune_keep_ = prune_keep_mask(map, s_.prune);
  return remove(map, prune_keep_);
}

std::size_t MapOptimizer::remove(GaussianMap& map, const std::vector<char>& keep) {
  adam_.compact(keep);
  blocks_.invalidate();
  return map.compact(keep);
}

std::size_t MapOptimizer::buffer_bytes() const {
  return raster_.cache_bytes() + prune_keep_.capacity() + blocks_.bytes() +
         dense_slot_.capacity() * sizeof(int);
}

std::size_t MapOptimizer::view_bytes() const {
  return render_.capacity_bytes() + (v_color_.capacity() + v_depth_.capacity()) * sizeof(float);
}

double MapOptimizer::bytes_per_gaussian(const GaussianMap& map) const {
  if (map.size() == 0) return 0.0;
  const std::size_t bytes = map.capacity_bytes() + moment_bytes() + buffer_bytes();
  return static_cast<double>(bytes) / static_cast<double>(map.size());
}

}  // namespace vigs::mapping
