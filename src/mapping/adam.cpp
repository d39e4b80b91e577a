#include "mapping/adam.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

namespace vigs::mapping {

namespace {
void update(std::vector<float>& p, const std::vector<float>& g, std::vector<std::uint16_t>& m,
            std::vector<float>& v, double lr, double b1, double b2, double eps, double bc1,
            double bc2) {
  const float fb1 = static_cast<float>(b1), fb2 = static_cast<float>(b2);
  const float step = static_cast<float>(lr / bc1);
  const float inv_sqrt_bc2 = static_cast<float>(1.0 / std::sqrt(bc2));
  const float feps = static_cast<float>(eps);
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    const float gi = g[i];
    const float mi = fb1 * from_bfloat16(m[i]) + (1.0f - fb1) * gi;  // as Adam::update_one
    m[i] = to_bfloat16(mi);
    v[i] = fb2 * v[i] + (1.0f - fb2) * gi * gi;
    p[i] -= step * mi / (std::sqrt(v[i]) * inv_sqrt_bc2 + feps);
  }
}
}  // namespace

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
  ++step_;
  const double bc1 = 1.0 - std::pow(s_.beta1, static_cast<double>(step_));
  const double bc2 = 1.0 - std::pow(s_.beta2, static_cast<double>(step_));
  update(params.mean_w, grad.mean_w, m_.mean_w, v_.mean_w, s_.lr_mean, s_.beta1, s_.beta2, s_.eps,
         bc1, bc2);
  update(params.log_scale, grad.log_scale, m_.log_scale, v_.log_scale, s_.lr_log_scale, s_.beta1,
         s_.beta2, s_.eps, bc1, bc2);
  update(params.quat_wxyz, grad.quat_wxyz, m_.quat_wxyz, v_.quat_wxyz, s_.lr_quat, s_.beta1,
         s_.beta2, s_.eps, bc1, bc2);
  update(params.opacity_logit, grad.opacity_logit, m_.opacity_logit, v_.opacity_logit,
         s_.lr_opacity, s_.beta1, s_.beta2, s_.eps, bc1, bc2);
  update(params.color_rgb, grad.color_rgb, m_.color_rgb, v_.color_rgb, s_.lr_color, s_.beta1,
         s_.beta2, s_.eps, bc1, bc2);
}

std::size_t Adam::bytes() const {
  return m_.capacity_bytes() + v_.capacity_bytes();
}

}  // namespace vigs::mapping
