#include "mapping/adam.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace vigs::mapping {

void Adam::grow(std::size_t n) {
  if (m_.size() >= n) return;
  const std::size_t old = m_.size();
  m_.resize(n);
  v_.resize(n);
  auto zero_tail = [&](auto& a) {  // bfloat16 zero is all bits zero, as float's
    using T = typename std::remove_reference_t<decltype(a.mean_w)>::value_type;
    std::fill(a.mean_w.begin() + 3 * old, a.mean_w.end(), T(0));
    std::fill(a.log_scale.begin() + 3 * old, a.log_scale.end(), T(0));
    std::fill(a.quat_wxyz.begin() + 4 * old, a.quat_wxyz.end(), T(0));
    std::fill(a.opacity_logit.begin() + old, a.opacity_logit.end(), T(0));
    std::fill(a.color_rgb.begin() + 3 * old, a.color_rgb.end(), T(0));
  };
  zero_tail(m_);
  zero_tail(v_);
  last_step_.resize(n, static_cast<std::uint32_t>(step_));
}

void Adam::mark_all_stepped() {
  std::fill(last_step_.begin(), last_step_.end(), static_cast<std::uint32_t>(step_));
}

Adam::Coeffs Adam::begin_step() {
  ++step_;
  const double bc1 = 1.0 - std::pow(s_.beta1, static_cast<double>(step_));
  const double bc2 = 1.0 - std::pow(s_.beta2, static_cast<double>(step_));
  Coeffs c;
  c.b1 = static_cast<float>(s_.beta1);
  c.b2 = static_cast<float>(s_.beta2);
  c.inv_sqrt_bc2 = static_cast<float>(1.0 / std::sqrt(bc2));
  c.eps = static_cast<float>(s_.eps);
  c.step_mean = static_cast<float>(s_.lr_mean / bc1);
  c.step_log_scale = static_cast<float>(s_.lr_log_scale / bc1);
  c.step_quat = static_cast<float>(s_.lr_quat / bc1);
  c.step_opacity = static_cast<float>(s_.lr_opacity / bc1);
  c.step_color = static_cast<float>(s_.lr_color / bc1);
  return c;
}

void Adam::step(GaussianMap& params, const GaussianMap& grad) {
  grow(params.size());
  const Coeffs c = begin_step();
  float g[14];  // the fused step's order: mean 3, log-scale 3, quaternion 4, opacity, colour 3
  for (std::size_t i = 0; i < params.size(); ++i) {
    for (std::size_t k = 0; k < 3; ++k) {
      g[k] = grad.mean_w[3 * i + k];
      g[3 + k] = grad.log_scale[3 * i + k];
      g[11 + k] = grad.color_rgb[3 * i + k];
    }
    for (std::size_t k = 0; k < 4; ++k) g[6 + k] = grad.quat_wxyz[4 * i + k];
    g[10] = grad.opacity_logit[i];
    update_gaussian(params, i, g, c);
  }
  mark_all_stepped();
}

std::size_t Adam::bytes() const {
  return m_.capacity_bytes() + v_.capacity_bytes() + last_step_.capacity() * sizeof(std::uint32_t);
}

}  // namespace vigs::mapping
