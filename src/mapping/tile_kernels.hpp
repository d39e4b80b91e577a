#pragma once
// Per-tile blending kernels (scalar reference). A tile's Gaussians are gathered, in depth order,
// into a contiguous array first so that the inner loop streams through memory.
#include <algorithm>
#include <cmath>
#include <limits>

#include "mapping/raster_settings.hpp"

namespace vigs::mapping {

template <class T>
struct TileGaussian {
  T x, y;              ///< mean2d, pixels
  T ca, cb, cc;        ///< conic
  T opacity;           ///< sigmoid(logit)
  T r, g, b;           ///< colour
  T z;                 ///< depth, metres
  T sigma_cut;         ///< alpha < min_alpha exactly when sigma > sigma_cut: skips exp far away
  T reach_x, reach_y;  ///< |dx|, |dy| beyond which sigma > sigma_cut (kernel_reach), pixels
};

/// ln(opacity / min_alpha), or a bound past which exp underflows when min_alpha is 0.
template <class T>
inline T sigma_cutoff(T opacity, double min_alpha) {
  return min_alpha > 0 ? std::log(opacity / T(min_alpha)) : T(80);
}

/// How far from its centre, across (rx) and down (ry) in pixels, a Gaussian can pass the
/// kernels' test sigma = d^T conic d / 2 <= sigma_cut at all: the ellipse's half extents
/// sqrt(2 sigma_cut Sigma_xx) and sqrt(2 sigma_cut Sigma_yy) (Sigma = conic^-1), with 1 % and
/// 0.01 px of slack for the kernels' rounding. Infinite when the conic is not positive
/// definite (no bound). Used to bin Gaussians into tiles and, inside a tile, to skip a row or
/// an 8-pixel run no pixel of which the Gaussian can reach: both leave the render unchanged.
template <class T>
inline void kernel_reach(const T conic[3], T sigma_cut, T& rx, T& ry) {
  const T det = conic[0] * conic[2] - conic[1] * conic[1];
  if (!(det > T(0)) || !(conic[0] > T(0))) {
    rx = ry = std::numeric_limits<T>::infinity();
    return;
  }
  const T cut2 = T(2) * std::max(T(0), sigma_cut);
  rx = std::sqrt(cut2 * conic[2] / det) * T(1.01) + T(0.01);
  ry = std::sqrt(cut2 * conic[0] / det) * T(1.01) + T(0.01);
}

/// True when a Gaussian cannot reach any pixel of the run [x_lo, x_hi] of row y (centre and
/// reach as in TileGaussian): the kernels skip it there without evaluating it. Always inlined:
/// the AVX2 kernels' translation units (-mavx2) call it too, and an out-of-line copy compiled
/// there could be the one the linker keeps for the portable kernels.
template <class T>
[[gnu::always_inline]] inline bool out_of_reach(const TileGaussian<T>& g, T x_lo, T x_hi, T y) {
  return std::abs(g.y - y) > g.reach_y || g.x + g.reach_x < x_lo || g.x - g.reach_x > x_hi;
}

/// Output pointers of one render, row-major per pixel.
template <class T>
struct PixelOutputs {
  int width = 0;
  T* color = nullptr;        ///< 3 per pixel
  T* depth = nullptr;        ///< 1 per pixel
  T* final_T = nullptr;      ///< 1 per pixel
  int* n_contrib = nullptr;  ///< 1 per pixel: index (+1) of the last contributor in the tile list
};

struct TileRect {
  int x0, y0, x1, y1;  ///< pixel range [x0, x1) x [y0, y1)
};

template <class T>
inline void forward_tile_scalar(const TileRect& rect, const TileGaussian<T>* gs, int count,
                                const RasterSettings& s, PixelOutputs<T>& out) {
  const T min_alpha = T(s.min_alpha), max_alpha = T(s.max_alpha);
  const T min_T = T(s.min_transmittance);
  for (int py = rect.y0; py < rect.y1; ++py) {
    for (int px = rect.x0; px < rect.x1; ++px) {
      T Tr = 1, c0 = 0, c1 = 0, c2 = 0, d = 0;
      int last = 0;
      for (int k = 0; k < count; ++k) {
        const TileGaussian<T>& g = gs[k];
        if (out_of_reach(g, T(px), T(px), T(py))) continue;
        const T dx = g.x - T(px), dy = g.y - T(py);
        const T sigma = T(0.5) * (g.ca * dx * dx + g.cc * dy * dy) + g.cb * dx * dy;
        if (sigma < T(0) || sigma > g.sigma_cut) continue;
        const T alpha = std::min(max_alpha, g.opacity * std::exp(-sigma));
        if (alpha < min_alpha) continue;
        const T next_T = Tr * (T(1) - alpha);
        if (next_T <= min_T) break;
        const T w = alpha * Tr;
        c0 += w * g.r;
        c1 += w * g.g;
        c2 += w * g.b;
        d += w * g.z;
        Tr = next_T;
        last = k + 1;
      }
      const int p = py * out.width + px;
      out.color[3 * p] = c0;
      out.color[3 * p + 1] = c1;
      out.color[3 * p + 2] = c2;
      out.depth[p] = d;
      out.final_T[p] = Tr;
      out.n_contrib[p] = last;
    }
  }
}

/// Per tile-Gaussian gradient accumulator: mean2d (2), conic (3), opacity, colour (3), depth.
template <class T>
struct TileGrad {
  T x, y, ca, cb, cc, opacity, r, g, b, z;
};

/// Reverse traversal from each pixel's last contributor. Adds into `grads` (one per tile
/// Gaussian). v_color: 3 per pixel; v_depth and v_alpha: 1 per pixel, either may be null.
template <class T>
inline void backward_tile_scalar(const TileRect& rect, const TileGaussian<T>* gs,
                                 const RasterSettings& s, int width, const T* final_T_img,
                                 const int* n_contrib_img, const T* v_color, const T* v_depth,
                                 const T* v_alpha, TileGrad<T>* grads) {
  const T min_alpha = T(s.min_alpha), max_alpha = T(s.max_alpha);
  for (int py = rect.y0; py < rect.y1; ++py) {
    for (int px = rect.x0; px < rect.x1; ++px) {
      const int p = py * width + px;
      const int last = n_contrib_img[p];
      if (last == 0) continue;
      const T T_final = final_T_img[p];
      const T vc0 = v_color[3 * p], vc1 = v_color[3 * p + 1], vc2 = v_color[3 * p + 2];
      const T vd = v_depth ? v_depth[p] : T(0);
      const T va = v_alpha ? v_alpha[p] : T(0);
      T Tr = T_final;
      T b0 = 0, b1 = 0, b2 = 0, bd = 0;
      for (int k = last - 1; k >= 0; --k) {
        const TileGaussian<T>& g = gs[k];
        if (out_of_reach(g, T(px), T(px), T(py))) continue;
        const T dx = g.x - T(px), dy = g.y - T(py);
        const T sigma = T(0.5) * (g.ca * dx * dx + g.cc * dy * dy) + g.cb * dx * dy;
        if (sigma < T(0) || sigma > g.sigma_cut) continue;
        const T vis = std::exp(-sigma);
        const T raw = g.opacity * vis;
        const T alpha = std::min(max_alpha, raw);
        if (alpha < min_alpha) continue;
        const T ra = T(1) / (T(1) - alpha);
        Tr *= ra;
        const T w = alpha * Tr;
        TileGrad<T>& gr = grads[k];
        gr.r += w * vc0;
        gr.g += w * vc1;
        gr.b += w * vc2;
        gr.z += w * vd;
        const T v_a = (g.r * Tr - b0 * ra) * vc0 + (g.g * Tr - b1 * ra) * vc1 +
                      (g.b * Tr - b2 * ra) * vc2 + (g.z * Tr - bd * ra) * vd + T_final * ra * va;
        b0 += g.r * w;
        b1 += g.g * w;
        b2 += g.b * w;
        bd += g.z * w;
        if (raw <= max_alpha) {
          const T v_sigma = -raw * v_a;
          gr.ca += T(0.5) * dx * dx * v_sigma;
          gr.cb += dx * dy * v_sigma;
          gr.cc += T(0.5) * dy * dy * v_sigma;
          gr.x += v_sigma * (g.ca * dx + g.cb * dy);
          gr.y += v_sigma * (g.cb * dx + g.cc * dy);
          gr.opacity += vis * v_a;
        }
      }
    }
  }
}

}  // namespace vigs::mapping
