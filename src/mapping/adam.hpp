#pragma once
// Adam with one learning rate per parameter group (mean, log-scale, quaternion, opacity logit,
// colour), moments kept in the same structure-of-arrays layout as the map.
#include <cstddef>
#include <vector>

#include "mapping/gaussian_map.hpp"

namespace vigs::mapping {

struct AdamSettings {
  double lr_mean = 4e-6;
  double lr_log_scale = 5e-3;
  double lr_quat = 1e-3;
  double lr_opacity = 0.05;
  double lr_color = 2.5e-3;
  double beta1 = 0.9;
  double beta2 = 0.999;
  double eps = 1e-15;  ///< as 3DGS
};

class Adam {
 public:
  explicit Adam(AdamSettings s = {}) : s_(s) {}

  [[nodiscard]] const AdamSettings& settings() const { return s_; }
  AdamSettings& settings() { return s_; }

  /// One step on every Gaussian, as torch.optim.Adam with one global step count: moments of
  /// newly appended Gaussians start at zero.
  void step(GaussianMap& params, const GaussianMap& grad);

  /// Applies the same compaction as GaussianParams::compact to the moments.
  template <class Mask>
  void compact(const Mask& keep) {
    m_.compact(keep);
    v_.compact(keep);
  }

  [[nodiscard]] long steps() const { return step_; }
  [[nodiscard]] std::size_t bytes() const;

 private:
  void grow(std::size_t n);

  AdamSettings s_;
  GaussianMap m_, v_;
  long step_ = 0;
};

}  // namespace vigs::mapping
