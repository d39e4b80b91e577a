#pragma once
// Adam with one learning rate per parameter group (mean, log-scale, quaternion, opacity logit,
// colour), moments kept in the same structure-of-arrays layout as the map. The first moment is
// stored as bfloat16 (bfloat16.hpp), the second as float: 84 B of moments per Gaussian instead
// of 112, a tenth of the live mapper's memory per Gaussian; with the step each Gaussian was last
// stepped at (4 B), 88 B.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/config/mapping_components.hpp"
#include "mapping/bfloat16.hpp"
#include "mapping/compact_kept.hpp"
#include "mapping/gaussian_map.hpp"

namespace vigs::mapping {

using config::AdamSettings;  // defaults: core/config/mapping_components.hpp

class Adam {
 public:
  explicit Adam(AdamSettings s = {}) : s_(s) {}

  [[nodiscard]] const AdamSettings& settings() const { return s_; }
  AdamSettings& settings() { return s_; }

  /// One step on every Gaussian, as torch.optim.Adam with one global step count: moments of
  /// newly appended Gaussians start at zero.
  void step(GaussianMap& params, const GaussianMap& grad);

  /// The same step with gradients supplied per Gaussian by grad_of(i, float g[14]) (order:
  /// mean 3, log-scale 3, quaternion 4, opacity logit, colour 3), so that no full gradient
  /// copy of the map is needed. `ranges` runs a callable(begin, end) over a split of [0, n).
  template <class GradFn, class Ranges>
  void step_fused(GaussianMap& p, GradFn&& grad_of, Ranges&& ranges) {
    grow(p.size());
    const Coeffs c = begin_step();
    ranges(p.size(), [&](std::size_t b, std::size_t e) {
      float gr[14];
      for (std::size_t i = b; i < e; ++i) {
        grad_of(i, gr);
        update_gaussian(p, i, gr, c);
      }
    });
    mark_all_stepped();
  }

  /// The fused step on the Gaussians listed in `ids` only (gsplat's "selective Adam"): the
  /// others keep their parameters and moments, where the dense step would still move them by
  /// their momentum. The step count stays global, as in gsplat. A view's iteration then costs
  /// what the view sees, not the whole map: on a 4 M-Gaussian office the dense step streams
  /// about 1.4 GB of parameters and moments per iteration for the few hundred thousand
  /// Gaussians one camera sees. grad_of(k, gr) gives the gradient of Gaussian ids[k]; `ids`
  /// holds each Gaussian once.
  ///
  /// A Gaussian skipped for Δ steps first has its moments decayed as the dense step would have
  /// decayed them (m·β1^Δ, v·β2^Δ), without the parameter moves the dense step would have made.
  /// Without this a Gaussian seen again after a minute resumes with the first moment of its
  /// last view and is pushed along it for the next ~10 steps; the view that brings it back into
  /// the frustum may see it only through a wall (the projection does not know occlusion), so a
  /// map region trained a minute earlier was degraded by views that never saw it: 2.4 dB of
  /// the uHumans-scale office's first-minute corridor at ground-truth poses (BENCHMARKS,
  /// "Where the first minute is lost"). gsplat's selective Adam leaves the moments as they
  /// were; its views come from a fixed training set, revisited every few hundred steps.
  template <class GradFn, class Ranges>
  void step_selected(GaussianMap& p, const std::vector<int>& ids, GradFn&& grad_of,
                     Ranges&& ranges) {
    grow(p.size());
    const Coeffs c = begin_step();
    ranges(ids.size(), [&](std::size_t b, std::size_t e) {
      float gr[14];
      for (std::size_t k = b; k < e; ++k) {
        const auto i = static_cast<std::size_t>(ids[k]);
        grad_of(k, gr);
        catch_up(i, c);
        update_gaussian(p, i, gr, c);
      }
    });
  }

  /// Applies the same compaction as GaussianParams::compact to the moments.
  template <class Mask>
  void compact(const Mask& keep) {
    m_.compact(keep);
    v_.compact(keep);
    compact_kept(last_step_, keep);
  }

  [[nodiscard]] long steps() const { return step_; }
  [[nodiscard]] std::size_t bytes() const;

 private:
  struct Coeffs {
    float b1, b2, inv_sqrt_bc2, eps;
    float step_mean, step_log_scale, step_quat, step_opacity, step_color;  ///< lr / bc1
  };
  Coeffs begin_step();
  /// Decays Gaussian i's moments over the steps it skipped and records this step as its last.
  /// Step counts are compared modulo 2^32, so a Δ under 2^32 steps (nearly a year at 100
  /// steps/s) is exact across the wrap.
  void catch_up(std::size_t i, const Coeffs& c) {
    const auto now = static_cast<std::uint32_t>(step_);
    const std::uint32_t skipped = now - 1u - last_step_[i];
    last_step_[i] = now;
    if (skipped == 0) return;
    const float d1 = std::pow(c.b1, static_cast<float>(skipped));
    const float d2 = std::pow(c.b2, static_cast<float>(skipped));
    auto decay = [&](std::uint16_t* m, float* v, std::size_t n) {
      for (std::size_t k = 0; k < n; ++k) {
        m[k] = to_bfloat16(d1 * from_bfloat16(m[k]));
        v[k] *= d2;
      }
    };
    decay(&m_.mean_w[3 * i], &v_.mean_w[3 * i], 3);
    decay(&m_.log_scale[3 * i], &v_.log_scale[3 * i], 3);
    decay(&m_.quat_wxyz[4 * i], &v_.quat_wxyz[4 * i], 4);
    decay(&m_.opacity_logit[i], &v_.opacity_logit[i], 1);
    decay(&m_.color_rgb[3 * i], &v_.color_rgb[3 * i], 3);
  }
  void mark_all_stepped();
  static void update_one(float& p, float g, std::uint16_t& m_bf16, float& v, const Coeffs& c,
                         float step) {
    const float m = c.b1 * from_bfloat16(m_bf16) + (1.0f - c.b1) * g;
    m_bf16 = to_bfloat16(m);
    v = c.b2 * v + (1.0f - c.b2) * g * g;
    p -= step * m / (std::sqrt(v) * c.inv_sqrt_bc2 + c.eps);
  }
  void update_gaussian(GaussianMap& p, std::size_t i, const float gr[14], const Coeffs& c) {
    for (std::size_t k = 0; k < 3; ++k) {
      update_one(p.mean_w[3 * i + k], gr[k], m_.mean_w[3 * i + k], v_.mean_w[3 * i + k], c,
                 c.step_mean);
      update_one(p.log_scale[3 * i + k], gr[3 + k], m_.log_scale[3 * i + k],
                 v_.log_scale[3 * i + k], c, c.step_log_scale);
      update_one(p.color_rgb[3 * i + k], gr[11 + k], m_.color_rgb[3 * i + k],
                 v_.color_rgb[3 * i + k], c, c.step_color);
    }
    for (std::size_t k = 0; k < 4; ++k)
      update_one(p.quat_wxyz[4 * i + k], gr[6 + k], m_.quat_wxyz[4 * i + k],
                 v_.quat_wxyz[4 * i + k], c, c.step_quat);
    update_one(p.opacity_logit[i], gr[10], m_.opacity_logit[i], v_.opacity_logit[i], c,
               c.step_opacity);
  }
  void grow(std::size_t n);

  AdamSettings s_;
  GaussianParams<std::uint16_t> m_;  ///< first moment, bfloat16
  GaussianMap v_;                    ///< second moment
  /// Per Gaussian, the step count (mod 2^32) of its last update, or of the last step before it
  /// was appended (its moments were zero until then).
  std::vector<std::uint32_t> last_step_;
  long step_ = 0;
};

}  // namespace vigs::mapping
