#pragma once
// Structural similarity over valid windows (the window always lies inside the image) with a
// separable window, and its gradient written out analytically. Valid windows make the three
// published conventions the same computation: scikit-image's 7x7 uniform window with a 3-pixel
// crop (sample covariance), its 11x11 Gaussian with a 5-pixel crop (population covariance) and
// pytorch-msssim's valid 11x11 Gaussian (sigma 1.5).
#include <cstddef>
#include <string>
#include <vector>

#include "rt/worker_team.hpp"

namespace vigs::mapping {

enum class SsimWindow { kGaussian11, kUniform7 };

/// Parses "gaussian11" or "uniform7"; throws std::invalid_argument otherwise.
SsimWindow parse_ssim_window(const std::string& name);

struct SsimOptions {
  SsimWindow window = SsimWindow::kGaussian11;
  bool sample_covariance = false;  ///< N/(N-1) correction (scikit-image's default)
  double data_range = 1.0;         ///< L: 1 for [0, 1] images, 255 for 8-bit values
  bool use_simd = true;    ///< floats: AVX2 filters where the CPU has them (simd_weighted_rows.hpp)
  bool use_avx512 = true;  ///< with use_simd: AVX-512 filters where the CPU has them (same bits)
};

/// The normalised 1D window (11 taps, sigma 1.5; or 7 uniform taps).
std::vector<double> ssim_window_1d(SsimWindow w);

/// SSIM of two interleaved images (channels per pixel) and optionally its gradient with respect
/// to `x`. `mask` (one per pixel, may be null) excludes windows whose centre pixel is 0. The
/// result is the mean over valid windows and channels. Scratch buffers are kept between calls.
template <class T>
class Ssim {
 public:
  /// `pool` (may be null) shares blocks of rows among its threads, each block claimed by whichever
  /// is free; it must outlive this object. The result does not depend on the pool's size.
  explicit Ssim(SsimOptions options = {}, rt::WorkerTeam* pool = nullptr);

  /// Returns mean SSIM; when grad_x is not null it receives d(mean SSIM)/dx (w*h*channels).
  T evaluate(const T* x, const T* y, int width, int height, int channels, const T* mask, T* grad_x);

  /// As evaluate(), but adds weight * d(mean SSIM)/dx to grad (w*h*channels, not null): a loss
  /// folds its SSIM term into the colour gradient it holds without a second image-sized pass.
  T evaluate_add_gradient(const T* x, const T* y, int width, int height, int channels,
                          const T* mask, T* grad, T weight);

  /// SsimOptions::use_avx512 after construction.
  void use_avx512(bool on) { opt_.use_avx512 = on; }

 private:
  static constexpr int kRowsPerBlock = 16;
  /// Window rows per strip of the forward pass (its input rows, K - 1 more, stay in cache).
  static constexpr int kStripRows = 32;
  /// evaluate() and evaluate_add_gradient(): grad_x[i] = dS/dx, or += weight * dS/dx with add.
  T run(const T* x, const T* y, int width, int height, int channels, const T* mask, T* grad_x,
        bool add, T weight);

  SsimOptions opt_;
  rt::WorkerTeam* pool_;
  std::vector<T> win_;
  std::vector<T> scratch_;       ///< per thread: strip rows, moments, row buffers (ssim.cpp)
  std::vector<T> g_;             ///< per channel: dS/d(mean x), d(mean x^2), d(mean xy) per window
  std::vector<double> partial_;  ///< per strip and channel, summed in strip order
  std::vector<std::size_t> valid_;  ///< windows on per row block
};

extern template class Ssim<float>;
extern template class Ssim<double>;

}  // namespace vigs::mapping
