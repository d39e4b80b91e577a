// SSIM and PSNR against the published reference values in ../shared/data/README.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "io/image_io.hpp"
#include "mapping/image_metrics.hpp"
#include "mapping/raster_simd.hpp"
#include "mapping/ssim.hpp"
#include "rt/worker_team.hpp"

namespace vigs::mapping {
namespace {

const std::string kImages = std::string(VIGS_SHARED_DATA_DIR) + "/images/";

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
  const auto a = io::read_image_u8(kImages + "kodim10.png");
  const auto b = io::read_image_u8(kImages + "simga_20_ssim_0.7857.png");
  std::vector<float> x(a.data.size()), y(b.data.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = a.data[i] / 255.0f;
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = b.data[i] / 255.0f;
  std::vector<float> mask(static_cast<std::size_t>(a.width) * a.height);
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = (i / 37) % 4 == 0 ? 0.0f : 1.0f;
  for (const auto& [window, sample] :
       {std::pair{SsimWindow::kGaussian11, false}, std::pair{SsimWindow::kUniform7, true}}) {
    const float* const masks[] = {nullptr, mask.data()};
    for (const float* m : masks) {
      SsimOptions simd_options{window, sample, 1.0};
      SsimOptions plain_options = simd_options;
      plain_options.use_simd = false;
      Ssim<float> simd(simd_options), plain(plain_options);
      std::vector<float> gs(x.size()), gp(x.size());
      const float vs = simd.evaluate(x.data(), y.data(), a.width, a.height, 3, m, gs.data());
      const float vp = plain.evaluate(x.data(), y.data(), a.width, a.height, 3, m, gp.data());
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

// Rows go in blocks to whichever thread is free and the mean is summed per block in block order:
// the value and the gradient do not depend on the team's size, with or without a mask.
TEST(MappingSsim, AnyTeamSizeGivesTheSameBits) {
  const auto a = io::read_image_u8(kImages + "kodim10.png");
  const auto b = io::read_image_u8(kImages + "simga_20_ssim_0.7857.png");
  std::vector<float> x(a.data.size()), y(b.data.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = a.data[i] / 255.0f;
  for (std::size_t i = 0; i < y.size(); ++i) y[i] = b.data[i] / 255.0f;
  std::vector<float> mask(static_cast<std::size_t>(a.width) * a.height);
  for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = (i / 37) % 4 == 0 ? 0.0f : 1.0f;
  const float* const masks[] = {nullptr, mask.data()};
  for (const float* m : masks) {
    Ssim<float> one;
    std::vector<float> g1(x.size());
    const float v1 = one.evaluate(x.data(), y.data(), a.width, a.height, 3, m, g1.data());
    for (const int members : {2, 3}) {
      rt::WorkerTeam pool(members);
      Ssim<float> many(SsimOptions{}, &pool);
      std::vector<float> gm(x.size());
      for (int round = 0; round < 2; ++round) {
        const float vm = many.evaluate(x.data(), y.data(), a.width, a.height, 3, m, gm.data());
        ASSERT_EQ(v1, vm) << members;
        ASSERT_EQ(g1, gm) << members;
      }
    }
  }
}

}  // namespace
}  // namespace vigs::mapping
