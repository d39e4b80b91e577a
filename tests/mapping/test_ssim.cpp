// SSIM and PSNR against the published reference values in ../shared/data/README.md.
#include <gtest/gtest.h>

#include <string>

#include "io/image_io.hpp"
#include "mapping/image_metrics.hpp"

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

}  // namespace
}  // namespace vigs::mapping
