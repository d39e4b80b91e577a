#include "mapping/image_metrics.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace vigs::mapping {

namespace {
void check_same(const ImageU8& a, const ImageU8& b) {
  if (a.width != b.width || a.height != b.height || a.channels != b.channels)
    throw std::invalid_argument("images differ in size or channels: " + std::to_string(a.width) +
                                "x" + std::to_string(a.height) + "x" + std::to_string(a.channels) +
                                " vs " + std::to_string(b.width) + "x" + std::to_string(b.height) +
                                "x" + std::to_string(b.channels));
  if (a.empty()) throw std::invalid_argument("empty image");
}
}  // namespace

double psnr_u8(const ImageU8& ref, const ImageU8& test) {
  check_same(ref, test);
  double se = 0;
  for (std::size_t i = 0; i < ref.data.size(); ++i) {
    const double d = static_cast<double>(ref.data[i]) - static_cast<double>(test.data[i]);
    se += d * d;
  }
  const double mse = se / static_cast<double>(ref.data.size());
  if (mse == 0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(255.0 * 255.0 / mse);
}

double ssim_u8(const ImageU8& ref, const ImageU8& test, SsimWindow window) {
  check_same(ref, test);
  std::vector<double> x(ref.data.begin(), ref.data.end()), y(test.data.begin(), test.data.end());
  SsimOptions o;
  o.window = window;
  o.sample_covariance = window == SsimWindow::kUniform7;
  o.data_range = 255.0;
  Ssim<double> ssim(o);
  return ssim.evaluate(y.data(), x.data(), ref.width, ref.height, ref.channels, nullptr, nullptr);
}

ImageQuality image_quality(const ImageU8& ref, const ImageU8& test, SsimWindow window) {
  return {psnr_u8(ref, test), ssim_u8(ref, test, window)};
}

}  // namespace vigs::mapping
