#pragma once
// The Gaussian map in structure-of-arrays form. One layout serves three uses: the map itself
// (float), gradients of the same shape, and a double-precision copy for gradient checks.
#include <cmath>
#include <cstddef>
#include <vector>

#include "core/capacity_bytes.hpp"
#include "core/grow_by_eighths.hpp"
#include "mapping/compact_kept.hpp"

namespace vigs::mapping {

/// Colour is stored as RGB in [0, 1] (spherical-harmonics degree 0 evaluated). Higher SH
/// degrees would add a `sh_rest` block of 3 * ((d + 1)^2 - 1) values per Gaussian; degree 0 is
/// what the mapper optimises today. PLY export converts to the 3DGS f_dc convention.
template <class T>
struct GaussianParams {
  std::vector<T> mean_w;         ///< 3 per Gaussian: position in the world frame, metres
  std::vector<T> log_scale;      ///< 3 per Gaussian: log of the standard deviations, log(m)
  std::vector<T> quat_wxyz;      ///< 4 per Gaussian: rotation body->world (w x y z), unnormalised
  std::vector<T> opacity_logit;  ///< 1 per Gaussian: opacity = sigmoid(logit)
  std::vector<T> color_rgb;      ///< 3 per Gaussian: linear RGB, nominally [0, 1]

  [[nodiscard]] std::size_t size() const { return opacity_logit.size(); }
  /// Every parameter of Gaussian i is finite (the prune removes, and the PLY writer leaves
  /// out, a Gaussian that is not).
  [[nodiscard]] bool finite(std::size_t i) const {
    bool ok = std::isfinite(opacity_logit[i]);
    for (std::size_t k = 0; k < 3; ++k)
      ok = ok && std::isfinite(mean_w[3 * i + k]) && std::isfinite(log_scale[3 * i + k]) &&
           std::isfinite(color_rgb[3 * i + k]);
    for (std::size_t k = 0; k < 4; ++k) ok = ok && std::isfinite(quat_wxyz[4 * i + k]);
    return ok;
  }
  /// Bytes held by the five arrays (their capacities).
  [[nodiscard]] std::size_t capacity_bytes() const {
    return vigs::capacity_bytes(mean_w, log_scale, quat_wxyz, opacity_logit, color_rgb);
  }

  /// Grows capacity by eighths, not doubling (core/grow_by_eighths.hpp).
  void resize(std::size_t n) {
    resize_by_eighths(mean_w, 3 * n);
    resize_by_eighths(log_scale, 3 * n);
    resize_by_eighths(quat_wxyz, 4 * n);
    resize_by_eighths(opacity_logit, n);
    resize_by_eighths(color_rgb, 3 * n);
  }
  void assign_zero(std::size_t n) {
    mean_w.assign(3 * n, T(0));
    log_scale.assign(3 * n, T(0));
    quat_wxyz.assign(4 * n, T(0));
    opacity_logit.assign(n, T(0));
    color_rgb.assign(3 * n, T(0));
  }
  void set_zero() { assign_zero(size()); }
  void reserve(std::size_t n) {
    mean_w.reserve(3 * n);
    log_scale.reserve(3 * n);
    quat_wxyz.reserve(4 * n);
    opacity_logit.reserve(n);
    color_rgb.reserve(3 * n);
  }

  /// Appends one Gaussian; `quat` is w x y z.
  void push_back(const T mean[3], const T log_s[3], const T quat[4], T logit, const T rgb[3]) {
    const std::size_t i = size();
    resize(i + 1);
    for (std::size_t k = 0; k < 3; ++k) {
      mean_w[3 * i + k] = mean[k];
      log_scale[3 * i + k] = log_s[k];
      color_rgb[3 * i + k] = rgb[k];
    }
    for (std::size_t k = 0; k < 4; ++k) quat_wxyz[4 * i + k] = quat[k];
    opacity_logit[i] = logit;
  }

  /// Keeps the Gaussians whose `keep[i]` is true, in order; returns the number removed.
  template <class Mask>
  std::size_t compact(const Mask& keep) {
    const std::size_t n = size();
    compact_kept(mean_w, keep, 3);
    compact_kept(log_scale, keep, 3);
    compact_kept(quat_wxyz, keep, 4);
    compact_kept(color_rgb, keep, 3);
    return n - compact_kept(opacity_logit, keep);
  }

  /// Number of scalar parameters per Gaussian (3 + 3 + 4 + 1 + 3).
  static constexpr int kParamsPerGaussian = 14;

  template <class U>
  [[nodiscard]] GaussianParams<U> cast() const {
    GaussianParams<U> out;
    auto conv = [](const std::vector<T>& a, std::vector<U>& b) { b.assign(a.begin(), a.end()); };
    conv(mean_w, out.mean_w);
    conv(log_scale, out.log_scale);
    conv(quat_wxyz, out.quat_wxyz);
    conv(opacity_logit, out.opacity_logit);
    conv(color_rgb, out.color_rgb);
    return out;
  }
};

using GaussianMap = GaussianParams<float>;

/// Opacity logit of a Gaussian removed from the map but not yet compacted away: its opacity
/// (1e-13) is far under any render's min_alpha, so the rasterizer culls it, and the next prune
/// (opacity under prune.min_opacity) compacts it out. Compacting a four-million-Gaussian map
/// and its Adam moments for every keyframe's few hundred see-through removals took a tenth of
/// the live mapper's time.
inline constexpr float kRemovedLogit = -30.0f;

template <class T>
inline T sigmoid(T x) {
  return T(1) / (T(1) + std::exp(-x));
}
template <class T>
inline T logit(T p) {
  return std::log(p / (T(1) - p));
}

}  // namespace vigs::mapping
