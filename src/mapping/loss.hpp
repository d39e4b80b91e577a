#pragma once
// Training loss of the map: (1 - lambda) L1(colour) + lambda (1 - SSIM) + lambda_D L1(depth).
// Colour terms are masked where the target depth is missing (when a target depth is given),
// unless color_without_depth (set with the far field); the depth term always is. A negative
// target depth marks a moving object's pixel (pipeline/moving_pixels.hpp): every term is masked
// there, also with color_without_depth, and SSIM leaves out every window that holds such a
// pixel (its gradient would reach the pixel);
// SSIM uses the 11x11 Gaussian window (sigma 1.5) over valid windows, with its analytic
// gradient.
#include <cstddef>
#include <vector>

#include "core/config/mapping_components.hpp"
#include "mapping/rasterizer.hpp"
#include "mapping/ssim.hpp"

namespace vigs::mapping {

using config::LossSettings;  // defaults: core/config/mapping_components.hpp

template <class T>
struct LossTerms {
  T total = 0;
  T l1_color = 0;
  T ssim = 0;
  T l1_depth_m = 0;
};

template <class T>
class PhotometricLoss {
 public:
  /// color_without_depth: colour terms also where the target has no depth (MapOptimizer sets it
  /// when the far field is on: every pixel then has Gaussians behind it to train).
  explicit PhotometricLoss(LossSettings s = {}, rt::WorkerTeam* pool = nullptr,
                           bool color_without_depth = false);

  /// target_rgb: 3 per pixel in [0, 1]; target_depth_m: 1 per pixel, 0 = missing, < 0 = moving
  /// (masked), may be null.
  /// Writes dL/d(colour) and dL/d(depth) (sizes 3 and 1 per pixel) when they are not null.
  LossTerms<T> evaluate(const RenderResult<T>& r, const T* target_rgb, const T* target_depth_m,
                        T* v_color, T* v_depth);

  [[nodiscard]] const LossSettings& settings() const { return s_; }
  /// SSIM's filters in AVX-512 where the CPU has them (the default) or AVX2 (a baseline for
  /// benchmarks: the same bits).
  void use_avx512(bool on) { ssim_.use_avx512(on); }

 private:
  /// mask_ without the SSIM windows that hold a moving pixel (ssim_mask_).
  const T* without_moving_windows(const T* target_depth_m, int width, int height);
  static constexpr int kRowsPerBlock = 16;
  /// One block of rows' share of the masks and sums.
  struct BlockSums {
    std::size_t n_mask = 0;
    bool moving = false;
    double l1_color = 0, l1_depth = 0;
  };

  LossSettings s_;
  bool color_without_depth_;
  rt::WorkerTeam* pool_;
  Ssim<T> ssim_;
  std::vector<T> mask_, ssim_mask_;
  std::vector<BlockSums> blocks_;
  std::vector<unsigned char> near_moving_;
};

extern template class PhotometricLoss<float>;
extern template class PhotometricLoss<double>;

}  // namespace vigs::mapping
