#pragma once
// Small random scenes shared by the mapping tests.
#include <cmath>
#include <random>
#include <vector>

#include "mapping/gaussian_map.hpp"
#include "mapping/render_camera.hpp"

namespace vigs::mapping::test {

/// A camera looking roughly along world +z from near the origin, with a small rotation.
inline RenderCamera small_camera(int w, int h, double f) {
  PinholeCamera k{w, h, f, f * 1.05, 0.5 * w - 0.3, 0.5 * h + 0.2};
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  T_w_c.linear() = (Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()) *
                    Eigen::AngleAxisd(-0.05, Eigen::Vector3d::UnitX()))
                       .toRotationMatrix();
  T_w_c.translation() = Eigen::Vector3d(0.1, -0.05, 0.2);
  return RenderCamera::from(k, T_w_c);
}

/// `n` Gaussians in front of small_camera(), opacity in [op_lo, op_hi].
template <class T>
GaussianParams<T> random_gaussians(int n, unsigned seed, double op_lo = 0.3, double op_hi = 0.7,
                                   double log_s_lo = -1.6, double log_s_hi = -0.9) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  GaussianParams<T> g;
  for (int i = 0; i < n; ++i) {
    const T mean[3] = {T(-0.5 + u(rng)), T(-0.4 + 0.8 * u(rng)), T(2.2 + 1.0 * u(rng))};
    const T ls[3] = {T(log_s_lo + (log_s_hi - log_s_lo) * u(rng)),
                     T(log_s_lo + (log_s_hi - log_s_lo) * u(rng)),
                     T(log_s_lo + (log_s_hi - log_s_lo) * u(rng))};
    T q[4] = {T(u(rng) - 0.5), T(u(rng) - 0.5), T(u(rng) - 0.5), T(u(rng) - 0.5)};
    q[0] += T(1.0);  // unnormalised on purpose
    const double op = op_lo + (op_hi - op_lo) * u(rng);
    const T rgb[3] = {T(u(rng)), T(u(rng)), T(u(rng))};
    g.push_back(mean, ls, q, T(std::log(op / (1 - op))), rgb);
  }
  return g;
}

/// Fixed, varied per-pixel loss gradients for a render of `pixels` pixels (colour 3 per pixel,
/// depth and accumulated opacity 1 each), for backward passes compared against each other.
struct PixelGradients {
  std::vector<float> color, depth, alpha;
  explicit PixelGradients(std::size_t pixels) : color(3 * pixels), depth(pixels), alpha(pixels) {
    for (std::size_t i = 0; i < color.size(); ++i)
      color[i] = 0.01f * static_cast<float>(i % 11) - 0.05f;
    for (std::size_t i = 0; i < depth.size(); ++i)
      depth[i] = 0.002f * static_cast<float>(i % 5) - 0.004f;
    for (std::size_t i = 0; i < alpha.size(); ++i)
      alpha[i] = 0.003f * static_cast<float>(i % 3) - 0.003f;
  }
};

}  // namespace vigs::mapping::test
