// Finite-difference checks in double precision of every parameter group (mean, log-scale,
// quaternion, opacity, colour) through projection, blending, depth, accumulated opacity and the
// full loss (L1 + SSIM + depth). The 1/255 cut-off is disabled so the function is smooth.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "mapping/loss.hpp"
#include "mapping/rasterizer.hpp"
#include "test_scene.hpp"

namespace vigs::mapping {
namespace {

using Params = GaussianParams<double>;

RasterSettings smooth_settings() {
  RasterSettings s;
  s.min_alpha = 0.0;
  return s;
}

struct Group {
  const char* name;
  std::vector<double> Params::*member;
};
const Group kGroups[] = {{"mean", &Params::mean_w},
                         {"log_scale", &Params::log_scale},
                         {"quat", &Params::quat_wxyz},
                         {"opacity_logit", &Params::opacity_logit},
                         {"color", &Params::color_rgb}};

/// Compares analytic gradients with central differences of `loss` for every parameter.
void check_all(Params g, const std::function<double(const Params&)>& loss, const Params& grad,
               double rel_tol) {
  const double h = 1e-6;
  for (const Group& grp : kGroups) {
    auto& vals = g.*grp.member;
    const auto& ana = grad.*grp.member;
    double worst = 0;
    for (std::size_t k = 0; k < vals.size(); ++k) {
      const double keep = vals[k];
      vals[k] = keep + h;
      const double lp = loss(g);
      vals[k] = keep - h;
      const double lm = loss(g);
      vals[k] = keep;
      const double num = (lp - lm) / (2 * h);
      const double err =
          std::abs(num - ana[k]) / std::max(1e-6, std::max(std::abs(num), std::abs(ana[k])));
      worst = std::max(worst, err);
      EXPECT_LT(err, rel_tol) << grp.name << "[" << k << "]: numeric " << num << " analytic "
                              << ana[k];
    }
    ::testing::Test::RecordProperty(std::string("worst_rel_err_") + grp.name,
                                    std::to_string(worst));
  }
}

/// Checks a random linear functional of colour, depth and accumulated opacity rendered from
/// `cam` (40 x 34 px).
void check_render_outputs(const RenderCamera& cam) {
  const Params g0 = test::random_gaussians<double>(6, 7);
  const std::size_t np = 40 * 34;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> wc(3 * np), wd(np), wa(np);
  for (auto& v : wc) v = u(rng);
  for (auto& v : wd) v = u(rng);
  for (auto& v : wa) v = u(rng);
  Rasterizer<double> ras(smooth_settings());
  auto loss = [&](const Params& g) {
    RenderResult<double> r;
    ras.forward(g, cam, r);
    double l = 0;
    for (std::size_t i = 0; i < np; ++i) {
      l += wc[3 * i] * r.color[3 * i] + wc[3 * i + 1] * r.color[3 * i + 1] +
           wc[3 * i + 2] * r.color[3 * i + 2] + wd[i] * r.depth[i] +
           wa[i] * r.alpha(static_cast<int>(i));
    }
    return l;
  };
  RenderResult<double> r;
  ras.forward(g0, cam, r);
  // every Gaussian must be visible for the check to mean something
  ASSERT_EQ(ras.visible_ids().size(), g0.size());
  Params grad;
  ras.backward(g0, cam, r, wc.data(), wd.data(), wa.data(), grad);
  check_all(g0, loss, grad, 1e-5);
}

TEST(MappingGradients, RenderOutputsLinearFunctional) {
  check_render_outputs(test::small_camera(40, 34, 40.0));
}

TEST(MappingGradients, RenderOutputsLinearFunctionalWithCoarserPixels) {
  // a camera one pyramid level down blurs by a quarter of the low-pass in its own pixels; the
  // backward pass must differentiate the same filter as the forward pass
  RenderCamera cam = test::small_camera(40, 34, 40.0);
  cam.pixel_size = 2.0;
  check_render_outputs(cam);
}

TEST(MappingGradients, FullLossWithSsimAndDepth) {
  const RenderCamera cam = test::small_camera(40, 34, 40.0);
  const Params g0 = test::random_gaussians<double>(6, 11);
  const std::size_t np = 40 * 34;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> target(3 * np), depth(np);
  for (auto& v : target) v = u(rng);
  for (std::size_t i = 0; i < np; ++i) depth[i] = (i % 7 == 3) ? 0.0 : 1.0 + 2.0 * u(rng);
  Rasterizer<double> ras(smooth_settings());
  // colour masked where the target has no depth, and (far field on) trained there too
  for (const bool color_without_depth : {false, true}) {
    PhotometricLoss<double> pl(LossSettings{0.2, 0.5}, nullptr, color_without_depth);
    auto loss = [&](const Params& g) {
      RenderResult<double> r;
      ras.forward(g, cam, r);
      return pl.evaluate(r, target.data(), depth.data(), nullptr, nullptr).total;
    };
    RenderResult<double> r;
    ras.forward(g0, cam, r);
    std::vector<double> vc(3 * np), vd(np);
    const auto terms = pl.evaluate(r, target.data(), depth.data(), vc.data(), vd.data());
    EXPECT_GT(terms.ssim, -1.0);
    EXPECT_GT(terms.l1_depth_m, 0.0);
    double no_depth_color = 0, no_depth_depth = 0;
    for (std::size_t i = 3; i < np; i += 7) {
      for (int c = 0; c < 3; ++c) no_depth_color += std::abs(vc[3 * i + c]);
      no_depth_depth += std::abs(vd[i]);
    }
    EXPECT_EQ(no_depth_depth, 0.0);
    if (color_without_depth) {
      EXPECT_GT(no_depth_color, 0.0);
    } else {
      // SSIM windows reach into masked pixels; the L1 term alone is zero there
      PhotometricLoss<double> l1_only(LossSettings{0.0, 0.5});
      l1_only.evaluate(r, target.data(), depth.data(), vc.data(), vd.data());
      for (std::size_t i = 3; i < np; i += 7)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(vc[3 * i + c], 0.0);
      ras.forward(g0, cam, r);
      pl.evaluate(r, target.data(), depth.data(), vc.data(), vd.data());
    }
    Params grad;
    ras.backward(g0, cam, r, vc.data(), vd.data(), nullptr, grad);
    check_all(g0, loss, grad, 1e-5);
  }
}

TEST(MappingGradients, SsimGradientMatchesFiniteDifferences) {
  const int w = 16, h = 14, c = 3;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> x(w * h * c), y(w * h * c), mask(w * h);
  for (auto& v : x) v = u(rng);
  for (auto& v : y) v = 0.5 * u(rng) + 0.25;
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = (i % 5 == 0) ? 0.0 : 1.0;
  for (bool sample : {false, true}) {
    for (auto win : {SsimWindow::kGaussian11, SsimWindow::kUniform7}) {
      Ssim<double> ssim(SsimOptions{win, sample, 1.0});
      std::vector<double> g(x.size());
      ssim.evaluate(x.data(), y.data(), w, h, c, mask.data(), g.data());
      for (std::size_t k = 0; k < x.size(); k += 3) {
        const double keep = x[k], e = 1e-6;
        x[k] = keep + e;
        const double lp = ssim.evaluate(x.data(), y.data(), w, h, c, mask.data(), nullptr);
        x[k] = keep - e;
        const double lm = ssim.evaluate(x.data(), y.data(), w, h, c, mask.data(), nullptr);
        x[k] = keep;
        const double num = (lp - lm) / (2 * e);
        EXPECT_NEAR(num, g[k], 1e-7 + 1e-5 * std::abs(num)) << "pixel value " << k;
      }
    }
  }
}

}  // namespace
}  // namespace vigs::mapping
