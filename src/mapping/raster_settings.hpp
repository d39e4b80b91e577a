#pragma once
// Constants of the splatting rasterizer (gsplat conventions). Tests change min_alpha to 0 so that
// finite differences see a smooth function.

namespace vigs::mapping {

inline constexpr int kTilePx = 16;  ///< square tiles, per-tile depth order

struct RasterSettings {
  double near_m = 0.01;             ///< Gaussians nearer than this are culled
  double eps2d_px2 = 0.3;           ///< low-pass added to the 2D covariance, in sensor pixels^2
                                    ///< (RenderCamera::lowpass_px2 scales it per resolution)
  double min_alpha = 1.0 / 255.0;   ///< contributions below this are skipped
  double max_alpha = 0.99;          ///< alpha clamp
  double min_transmittance = 1e-4;  ///< a pixel stops once T would fall to this
  bool use_simd = true;             ///< SIMD blending kernels when the CPU has them (float only)
  /// With use_simd: the AVX-512 kernels (8 x 2 pixels per vector) when the CPU has
  /// AVX-512 F and DQ; false keeps the AVX2 kernels (the benchmarks' baseline).
  bool use_avx512 = true;
  /// Inside a tile, skip a Gaussian for a row or 8-pixel run it cannot reach (kernel_reach):
  /// the render and gradients are bit-identical either way; false is the benchmarks' baseline.
  bool skip_out_of_reach = true;
};

}  // namespace vigs::mapping
