// SSIM and PSNR against the published reference values in ../shared/data/README.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "io/image_io.hpp"
#include "mapping/image_metrics.hpp"
#include "mapping/raster_simd.hpp"
#include "mapping/simd_weighted_rows.hpp"
#include "mapping/ssim.hpp"
#include "rt/worker_team.hpp"

namespace vigs::mapping {
namespace {

const std::string kImages = std::string(VIGS_SHARED_DATA_DIR) + "/images/";

/// kodim10 and its sigma-20 noisy copy as RGB floats in [0, 1], and a mask that leaves out every
/// fourth run of 37 pixels: the inputs of the tests that compare SSIM's implementations.
struct NoisyPair {
  std::vector<float> x, y, mask;
  int width = 0, height = 0;
};

const NoisyPair& noisy_pair() {
  static const NoisyPair pair = [] {
    const auto a = io::read_image_u8(kImages + "kodim10.png");
    const auto b = io::read_image_u8(kImages + "simga_20_ssim_0.7857.png");
    NoisyPair p;
    p.width = a.width;
    p.height = a.height;
    p.x.resize(a.data.size());
    p.y.resize(b.data.size());
    for (std::size_t i = 0; i < p.x.size(); ++i) p.x[i] = a.data[i] / 255.0f;
    for (std::size_t i = 0; i < p.y.size(); ++i) p.y[i] = b.data[i] / 255.0f;
    p.mask.resize(static_cast<std::size_t>(a.width) * a.height);
    for (std::size_t i = 0; i < p.mask.size(); ++i) p.mask[i] = (i / 37) % 4 == 0 ? 0.0f : 1.0f;
    return p;
  }();
  return pair;
}

TEST(MappingSsim, CameraUniform7SampleCovarianceMatchesScikitImage) {
  const auto a = io::read_image_u8(kImages + "camera.png");
  const auto b = io::read_image_u8(kImages + "camera_noisy.png");
  ASSERT_EQ(a.channels, 1);
  EXPECT_NEAR(ssim_u8(a, b, SsimWindow::kUniform7), 0.36745183279, 1e-9);
}

TEST(MappingSsim, CameraGaussian11MatchesScikitImage) {
  const auto a = io::read_image_u8(kImages + "camera.png");
  const auto b = io::read_image_u8(kImages + "camera_noisy.png");
  EXPECT_NEAR(ssim_u8(a, b, SsimWindow::kGaussian11), 0.35796, 5e-6);
}

TEST(MappingSsim, CameraPsnr) {
  const auto a = io::read_image_u8(kImages + "camera.png");
  const auto b = io::read_image_u8(kImages + "camera_noisy.png");
  EXPECT_NEAR(psnr_u8(a, b), 22.409353, 1e-6);
}

TEST(MappingSsim, Kodim10NoisyCopiesMatchPytorchMsssim) {
  const auto ref = io::read_image_u8(kImages + "kodim10.png");
  ASSERT_EQ(ref.channels, 3);
  const std::pair<const char*, double> cases[] = {{"simga_10_ssim_0.9325.png", 0.9325},
                                                  {"simga_20_ssim_0.7857.png", 0.7857}};
  for (const auto& [file, expected] : cases) {
    const auto test = io::read_image_u8(kImages + file);
    EXPECT_NEAR(ssim_u8(ref, test, SsimWindow::kGaussian11), expected, 1e-3) << file;
  }
}

TEST(MappingSsim, IdenticalImagesAndBadInput) {
  const auto a = io::read_image_u8(kImages + "camera.png");
  EXPECT_DOUBLE_EQ(ssim_u8(a, a, SsimWindow::kGaussian11), 1.0);
  ImageU8 small(5, 5, 1);
  EXPECT_THROW(ssim_u8(a, small, SsimWindow::kGaussian11), std::invalid_argument);
  EXPECT_THROW(ssim_u8(small, small, SsimWindow::kGaussian11), std::invalid_argument);
  EXPECT_THROW(parse_ssim_window("box3"), std::invalid_argument);
}

// The AVX2 filters and map rows against the plain loops: both windows (the uniform one with the
// sample covariance), with and without a mask; 768 px rows leave a partial last step of lanes.
TEST(MappingSsim, Avx2KernelsMatchThePlainLoopsInFloat) {
  if (!avx2_kernel_available()) GTEST_SKIP() << "no AVX2 on this CPU/architecture";
  const auto& [x, y, mask, width, height] = noisy_pair();
  for (const auto& [window, sample] :
       {std::pair{SsimWindow::kGaussian11, false}, std::pair{SsimWindow::kUniform7, true}}) {
    const float* const masks[] = {nullptr, mask.data()};
    for (const float* m : masks) {
      SsimOptions simd_options{window, sample, 1.0};
      SsimOptions plain_options = simd_options;
      plain_options.use_simd = false;
      Ssim<float> simd(simd_options), plain(plain_options);
      std::vector<float> gs(x.size()), gp(x.size());
      const float vs = simd.evaluate(x.data(), y.data(), width, height, 3, m, gs.data());
      const float vp = plain.evaluate(x.data(), y.data(), width, height, 3, m, gp.data());
      EXPECT_NEAR(vs, vp, 1e-5f);
      if (!m && window == SsimWindow::kGaussian11) {
        EXPECT_NEAR(vs, 0.7857f, 1e-3f);
      }
      float scale = 0, worst = 0;
      for (std::size_t i = 0; i < gp.size(); ++i) {
        scale = std::max(scale, std::abs(gp[i]));
        worst = std::max(worst, std::abs(gs[i] - gp[i]));
      }
      EXPECT_GT(scale, 0.0f);
      EXPECT_LT(worst, 1e-4f * scale) << (m ? "masked" : "whole");
    }
  }
}

// The AVX-512 row filters give the AVX2 ones' bits (both sum each output's taps in order with one
// fused multiply-add per tap): every row length up to 200 (all of both versions' tails), whole
// and truncated windows, rows at unaligned offsets; nothing is written past the row. Then the
// whole SSIM, value and gradient, with either.
TEST(MappingSsim, Avx512FiltersGiveTheAvx2Bits) {
  if (!avx512_kernel_available()) GTEST_SKIP() << "no AVX-512 on this CPU/architecture";
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f), weight(0.01f, 0.3f);
  std::vector<std::vector<float>> rows(11, std::vector<float>(220));
  for (auto& r : rows)
    for (float& v : r) v = value(rng);
  float w[11];
  for (float& v : w) v = weight(rng);
  constexpr float kSentinel = 7.0f;
  for (int n = 1; n <= 200; ++n) {
    for (const int n_rows : {1, 6, 11}) {
      const float* taps[11];
      for (int k = 0; k < 11; ++k) taps[k] = rows[static_cast<std::size_t>(k)].data() + k % 3;
      std::vector<float> o512(static_cast<std::size_t>(n) + 16, kSentinel), o2 = o512, plain = o512;
      weighted_rows_avx512(o512.data(), taps, w, n_rows, n);
      weighted_rows_avx2(o2.data(), taps, w, n_rows, n);
      weighted_rows_plain(plain.data(), taps, w, n_rows, n);
      ASSERT_EQ(o512, o2) << n << " outputs, " << n_rows << " taps";
      for (int i = 0; i < n; ++i)
        ASSERT_NEAR(o512[static_cast<std::size_t>(i)], plain[static_cast<std::size_t>(i)], 1e-5f);
    }
  }
  const auto& [x, y, mask, width, height] = noisy_pair();
  SsimOptions avx2_options;
  avx2_options.use_avx512 = false;
  Ssim<float> wide, narrow(avx2_options);
  std::vector<float> gw(x.size()), gn(x.size());
  const float vw = wide.evaluate(x.data(), y.data(), width, height, 3, nullptr, gw.data());
  const float vn = narrow.evaluate(x.data(), y.data(), width, height, 3, nullptr, gn.data());
  EXPECT_EQ(vw, vn);
  EXPECT_EQ(gw, gn);
}

// evaluate() writes every pixel's gradient (a stale buffer is overwritten, no zeroing pass), and
// evaluate_add_gradient() adds weight times that gradient to what the buffer holds, to the bit.
// With no window on, SSIM is 1, evaluate() writes zeros and the sum is left as it was.
TEST(MappingSsim, GradientAddedInPlaceIsTheWeightedGradient) {
  const auto& [x, y, mask, width, height] = noisy_pair();
  const float kNan = std::numeric_limits<float>::quiet_NaN();
  Ssim<float> ssim;
  std::vector<float> fresh(x.size(), 0.0f), stale(x.size(), kNan);
  const float v = ssim.evaluate(x.data(), y.data(), width, height, 3, mask.data(), fresh.data());
  EXPECT_EQ(ssim.evaluate(x.data(), y.data(), width, height, 3, mask.data(), stale.data()), v);
  EXPECT_EQ(stale, fresh);
  std::vector<float> sum(x.size());
  for (std::size_t i = 0; i < sum.size(); ++i) sum[i] = 0.001f * static_cast<float>(i % 97);
  const std::vector<float> before = sum;
  const float weight = -0.2f;
  EXPECT_EQ(ssim.evaluate_add_gradient(x.data(), y.data(), width, height, 3, mask.data(),
                                       sum.data(), weight),
            v);
  for (std::size_t i = 0; i < sum.size(); ++i)
    ASSERT_EQ(sum[i], before[i] + weight * fresh[i]) << "element " << i;
  const std::vector<float> off(mask.size(), 0.0f);
  std::fill(stale.begin(), stale.end(), kNan);
  EXPECT_EQ(ssim.evaluate(x.data(), y.data(), width, height, 3, off.data(), stale.data()), 1.0f);
  for (const float g : stale) ASSERT_EQ(g, 0.0f);
  std::vector<float> kept = before;
  EXPECT_EQ(ssim.evaluate_add_gradient(x.data(), y.data(), width, height, 3, off.data(),
                                       kept.data(), weight),
            1.0f);
  EXPECT_EQ(kept, before);
}

// Rows go in blocks to whichever thread is free and the mean is summed per block in block order:
// the value and the gradient do not depend on the team's size, with or without a mask.
TEST(MappingSsim, AnyTeamSizeGivesTheSameBits) {
  const auto& [x, y, mask, width, height] = noisy_pair();
  const float* const masks[] = {nullptr, mask.data()};
  for (const float* m : masks) {
    Ssim<float> one;
    std::vector<float> g1(x.size());
    const float v1 = one.evaluate(x.data(), y.data(), width, height, 3, m, g1.data());
    for (const int members : {2, 3}) {
      rt::WorkerTeam pool(members);
      Ssim<float> many(SsimOptions{}, &pool);
      std::vector<float> gm(x.size());
      for (int round = 0; round < 2; ++round) {
        const float vm = many.evaluate(x.data(), y.data(), width, height, 3, m, gm.data());
        ASSERT_EQ(v1, vm) << members;
        ASSERT_EQ(g1, gm) << members;
      }
    }
  }
}

}  // namespace
}  // namespace vigs::mapping
