#pragma once
// Image quality of 8-bit images: PSNR (peak 255) and SSIM over valid windows with L = 255,
// the mean over channels. Both images must have the same size and channel count.
#include "core/types/image.hpp"
#include "mapping/ssim.hpp"

namespace vigs::mapping {

struct ImageQuality {
  double psnr_db = 0;  ///< +inf for identical images
  double ssim = 0;
};

/// Throws std::invalid_argument when the images differ in size or channels.
double psnr_u8(const ImageU8& ref, const ImageU8& test);
double ssim_u8(const ImageU8& ref, const ImageU8& test, SsimWindow window);

/// The conventions the project reports: Gaussian 11x11 with population covariance (3DGS papers,
/// pytorch-msssim), or scikit-image's default uniform 7x7 with sample covariance.
ImageQuality image_quality(const ImageU8& ref, const ImageU8& test, SsimWindow window);

}  // namespace vigs::mapping
