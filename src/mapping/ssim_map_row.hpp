#pragma once
// One row of SSIM's map and of its partial derivatives with respect to the window moments: the
// per-window arithmetic of ssim.cpp between its forward and transposed filters. The AVX2 + FMA
// version lives in its own translation unit (ssim_map_row_avx2.cpp, -mavx2 -mfma) and is chosen
// at run time (raster_simd.hpp); the plain loop serves doubles and other CPUs.

namespace vigs::mapping {

/// The constants of one SSIM evaluation: C1, C2, the covariance correction cn (N/(N-1) or 1) and
/// the weight of one window in the mean (1 / (windows * channels)).
template <class T>
struct SsimRowTerms {
  T C1, C2, cn, inv_n;
};

/// For the n windows of a row, given their moments m[0..4] = mean x, mean y, mean x^2, mean y^2,
/// mean xy: returns the sum of SSIM over the windows whose centre is on (`on_mask[i] > 0`; all
/// when on_mask is null) and, when g is not null, writes dS/d(mean x), dS/d(mean x^2) and
/// dS/d(mean xy), each times inv_n (0 where off), to g[0][i], g[1][i], g[2][i].
template <class T>
double ssim_map_row_plain(const T* const* m, const T* on_mask, const SsimRowTerms<T>& t,
                          T* const* g, int n) {
  double sum = 0;
  const T two = T(2);
  for (int i = 0; i < n; ++i) {
    const bool on = !on_mask || on_mask[i] > T(0);
    const T ux = m[0][i], uy = m[1][i];
    const T vx = t.cn * (m[2][i] - ux * ux), vy = t.cn * (m[3][i] - uy * uy);
    const T vxy = t.cn * (m[4][i] - ux * uy);
    const T N1 = two * ux * uy + t.C1, N2 = two * vxy + t.C2;
    const T D1 = ux * ux + uy * uy + t.C1, D2 = vx + vy + t.C2;
    const T S = (N1 * N2) / (D1 * D2);
    if (on) sum += static_cast<double>(S);
    if (g) {
      const T wgt = on ? t.inv_n : T(0);
      g[0][i] =
          wgt * S * (two * uy / N1 - two * t.cn * uy / N2 - two * ux / D1 + two * t.cn * ux / D2);
      g[1][i] = wgt * (-S * t.cn / D2);
      g[2][i] = wgt * (S * two * t.cn / N2);
    }
  }
  return sum;
}

/// The same for floats, AVX2 where the CPU has it. The sum and the derivatives can differ from
/// the plain loop's in the last bits (fused multiply-adds, lane-wise partial sums), but are the
/// same run to run on one CPU.
double ssim_map_row(const float* const* m, const float* on_mask, const SsimRowTerms<float>& t,
                    float* const* g, int n);

/// Only call when avx2_kernel_available() (raster_simd.hpp).
double ssim_map_row_avx2(const float* const* m, const float* on_mask, const SsimRowTerms<float>& t,
                         float* const* g, int n);

}  // namespace vigs::mapping
