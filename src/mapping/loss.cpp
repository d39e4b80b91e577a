#include "mapping/loss.hpp"

#include <cmath>

namespace vigs::mapping {

template <class T>
PhotometricLoss<T>::PhotometricLoss(LossSettings s, rt::WorkerTeam* pool, bool color_without_depth)
    : s_(s), color_without_depth_(color_without_depth), ssim_(SsimOptions{}, pool) {}

template <class T>
LossTerms<T> PhotometricLoss<T>::evaluate(const RenderResult<T>& r, const T* target_rgb,
                                          const T* target_depth_m, T* v_color, T* v_depth) {
  const std::size_t np = static_cast<std::size_t>(r.width) * r.height;
  const T lam = T(s_.lambda_ssim), lam_d = T(s_.lambda_depth);
  const T* mask = nullptr;
  std::size_t n_mask = np;
  if (target_depth_m) {
    mask_.resize(np);
    n_mask = 0;
    for (std::size_t i = 0; i < np; ++i) {
      mask_[i] = color_without_depth_ || target_depth_m[i] > T(0) ? T(1) : T(0);
      n_mask += mask_[i] > T(0) ? 1 : 0;
    }
    mask = mask_.data();
  }
  LossTerms<T> out;
  // L1 colour
  double l1 = 0;
  const T inv_c = n_mask ? T(1) / (T(3) * T(n_mask)) : T(0);
  for (std::size_t i = 0; i < np; ++i) {
    const bool on = !mask || mask[i] > T(0);
    for (int c = 0; c < 3; ++c) {
      const T d = r.color[3 * i + c] - target_rgb[3 * i + c];
      if (on) l1 += static_cast<double>(std::abs(d));
      if (v_color) {
        const T sgn = d > T(0) ? T(1) : (d < T(0) ? T(-1) : T(0));
        v_color[3 * i + c] = on ? (T(1) - lam) * inv_c * sgn : T(0);
      }
    }
  }
  out.l1_color = T(l1) * inv_c;
  // SSIM
  if (v_color) ssim_grad_.resize(3 * np);
  out.ssim = ssim_.evaluate(r.color.data(), target_rgb, r.width, r.height, 3, mask,
                            v_color ? ssim_grad_.data() : nullptr);
  if (v_color)
    for (std::size_t i = 0; i < 3 * np; ++i) v_color[i] -= lam * ssim_grad_[i];
  // L1 depth
  if (v_depth)
    for (std::size_t i = 0; i < np; ++i) v_depth[i] = T(0);
  if (target_depth_m && lam_d > T(0) && n_mask > 0) {
    double l1d = 0;
    const T inv_d = T(1) / T(n_mask);
    for (std::size_t i = 0; i < np; ++i) {
      if (!(target_depth_m[i] > T(0))) continue;
      const T d = r.depth[i] - target_depth_m[i];
      l1d += static_cast<double>(std::abs(d));
      if (v_depth) v_depth[i] = lam_d * inv_d * (d > T(0) ? T(1) : (d < T(0) ? T(-1) : T(0)));
    }
    out.l1_depth_m = T(l1d) * inv_d;
  }
  out.total = (T(1) - lam) * out.l1_color + lam * (T(1) - out.ssim) + lam_d * out.l1_depth_m;
  return out;
}

template class PhotometricLoss<float>;
template class PhotometricLoss<double>;

}  // namespace vigs::mapping
