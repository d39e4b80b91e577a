#include "mapping/loss.hpp"

#include <algorithm>
#include <cmath>

#include "mapping/row_blocks.hpp"

namespace vigs::mapping {

template <class T>
PhotometricLoss<T>::PhotometricLoss(LossSettings s, rt::WorkerTeam* pool, bool color_without_depth)
    : s_(s), color_without_depth_(color_without_depth), pool_(pool), ssim_(SsimOptions{}, pool) {}

// The per-pixel passes run over blocks of rows on the pool (they were the mapper's longest serial
// stretch); the sums are kept per block and added in block order, so the result does not depend
// on which thread took which block, and the gradients (per pixel, with integer counts) are the
// same bits as one pass gives.
template <class T>
LossTerms<T> PhotometricLoss<T>::evaluate(const RenderResult<T>& r, const T* target_rgb,
                                          const T* target_depth_m, T* v_color, T* v_depth) {
  const std::size_t w = static_cast<std::size_t>(r.width);
  const std::size_t np = w * static_cast<std::size_t>(r.height);
  const T lam = T(s_.lambda_ssim), lam_d = T(s_.lambda_depth);
  const T* mask = nullptr;
  const T* ssim_mask = nullptr;
  std::size_t n_mask = np;
  blocks_.assign(row_block_count(r.height, kRowsPerBlock), BlockSums{});
  if (target_depth_m) {
    mask_.resize(np);
    for_row_blocks(pool_, r.height, kRowsPerBlock, [&](int, int b, int r0, int r1) {
      std::size_t n = 0;
      bool moving = false;
      for (std::size_t i = static_cast<std::size_t>(r0) * w; i < static_cast<std::size_t>(r1) * w;
           ++i) {
        // depth < 0: a moving object (a person) stood there; neither colour nor depth is a target
        const T d = target_depth_m[i];
        moving = moving || d < T(0);
        mask_[i] = d > T(0) || (color_without_depth_ && !(d < T(0))) ? T(1) : T(0);
        n += mask_[i] > T(0) ? 1 : 0;
      }
      blocks_[static_cast<std::size_t>(b)].n_mask = n;
      blocks_[static_cast<std::size_t>(b)].moving = moving;
    });
    n_mask = 0;
    bool moving = false;
    for (const BlockSums& b : blocks_) {
      n_mask += b.n_mask;
      moving = moving || b.moving;
    }
    mask = mask_.data();
    ssim_mask = moving ? without_moving_windows(target_depth_m, r.width, r.height) : mask;
  }
  const T inv_c = n_mask ? T(1) / (T(3) * T(n_mask)) : T(0);
  const bool depth_term = target_depth_m && lam_d > T(0) && n_mask > 0;
  const T inv_d = n_mask ? T(1) / T(n_mask) : T(0);
  // L1 colour and L1 depth with their gradients
  for_row_blocks(pool_, r.height, kRowsPerBlock, [&](int, int b, int r0, int r1) {
    double l1 = 0, l1d = 0;
    for (std::size_t i = static_cast<std::size_t>(r0) * w; i < static_cast<std::size_t>(r1) * w;
         ++i) {
      const bool on = !mask || mask[i] > T(0);
      for (int c = 0; c < 3; ++c) {
        const T d = r.color[3 * i + c] - target_rgb[3 * i + c];
        if (on) l1 += static_cast<double>(std::abs(d));
        if (v_color) {
          const T sgn = d > T(0) ? T(1) : (d < T(0) ? T(-1) : T(0));
          v_color[3 * i + c] = on ? (T(1) - lam) * inv_c * sgn : T(0);
        }
      }
      if (v_depth) v_depth[i] = T(0);
      if (!depth_term || !(target_depth_m[i] > T(0))) continue;
      const T d = r.depth[i] - target_depth_m[i];
      l1d += static_cast<double>(std::abs(d));
      if (v_depth) v_depth[i] = lam_d * inv_d * (d > T(0) ? T(1) : (d < T(0) ? T(-1) : T(0)));
    }
    blocks_[static_cast<std::size_t>(b)].l1_color = l1;
    blocks_[static_cast<std::size_t>(b)].l1_depth = l1d;
  });
  double l1 = 0, l1d = 0;
  for (const BlockSums& b : blocks_) {
    l1 += b.l1_color;
    l1d += b.l1_depth;
  }
  LossTerms<T> out;
  out.l1_color = T(l1) * inv_c;
  if (depth_term) out.l1_depth_m = T(l1d) * inv_d;
  // SSIM, its gradient added to the colour gradient in the same pass that computes it
  out.ssim = v_color ? ssim_.evaluate_add_gradient(r.color.data(), target_rgb, r.width, r.height, 3,
                                                   ssim_mask, v_color, -lam)
                     : ssim_.evaluate(r.color.data(), target_rgb, r.width, r.height, 3, ssim_mask,
                                      nullptr);
  out.total = (T(1) - lam) * out.l1_color + lam * (T(1) - out.ssim) + lam_d * out.l1_depth_m;
  return out;
}

// SSIM windows are excluded when any of their pixels is moving, not only their centre: the
// gradient of a window reaches all of its pixels, and a moving pixel must get none. A running
// count over rows, then over columns (Chebyshev distance <= the window's half-width).
template <class T>
const T* PhotometricLoss<T>::without_moving_windows(const T* target_depth_m, int width,
                                                    int height) {
  const int half = static_cast<int>(ssim_window_1d(SsimOptions{}.window).size() / 2);
  const std::size_t np = static_cast<std::size_t>(width) * height;
  near_moving_.assign(np, 0);
  for (int v = 0; v < height; ++v) {
    const T* d = target_depth_m + static_cast<std::size_t>(v) * width;
    unsigned char* out = near_moving_.data() + static_cast<std::size_t>(v) * width;
    int count = 0;  // moving pixels in [u - half, u + half] of this row
    for (int u = 0; u < std::min(half, width); ++u) count += d[u] < T(0) ? 1 : 0;
    for (int u = 0; u < width; ++u) {
      if (u + half < width) count += d[u + half] < T(0) ? 1 : 0;
      if (u - half - 1 >= 0) count -= d[u - half - 1] < T(0) ? 1 : 0;
      out[u] = count > 0 ? 1 : 0;
    }
  }
  ssim_mask_.assign(mask_.begin(), mask_.end());
  for (int u = 0; u < width; ++u) {
    auto at = [&](int v) { return near_moving_[static_cast<std::size_t>(v) * width + u]; };
    int count = 0;
    for (int v = 0; v < std::min(half, height); ++v) count += at(v);
    for (int v = 0; v < height; ++v) {
      if (v + half < height) count += at(v + half);
      if (v - half - 1 >= 0) count -= at(v - half - 1);
      if (count > 0) ssim_mask_[static_cast<std::size_t>(v) * width + u] = T(0);
    }
  }
  return ssim_mask_.data();
}

template class PhotometricLoss<float>;
template class PhotometricLoss<double>;

}  // namespace vigs::mapping
