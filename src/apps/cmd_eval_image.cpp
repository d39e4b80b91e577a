// `vigs eval image --ref A --test B [--ssim-window gaussian11|uniform7]`: PSNR and SSIM as JSON.
#include <cmath>
#include <iostream>
#include <string>

#include "apps/commands.hpp"
#include "apps/eval_group.hpp"
#include "io/image_io.hpp"
#include "io/json_text.hpp"
#include "mapping/image_metrics.hpp"

namespace vigs::apps {

void add_eval_image_command(CLI::App& app, ExitCode& exit_code) {
  auto* cmd = eval_group(app)->add_subcommand(
      "image", "PSNR (peak 255) and SSIM of an 8-bit test image against a reference, as JSON");
  static std::string ref, test, window = "gaussian11";
  cmd->add_option("--ref", ref, "reference image (PNG or JPEG)")->required();
  cmd->add_option("--test", test, "image to evaluate, same size and channels")->required();
  cmd->add_option("--ssim-window", window,
                  "gaussian11: 11x11 Gaussian, sigma 1.5, population covariance (3DGS papers); "
                  "uniform7: 7x7 uniform, sample covariance (scikit-image default)")
      ->check(CLI::IsMember({"gaussian11", "uniform7"}))
      ->capture_default_str();
  cmd->callback([&exit_code] {
    try {
      const auto a = io::read_image_u8(ref);
      const auto b = io::read_image_u8(test);
      if (a.channels != b.channels || a.width != b.width || a.height != b.height) {
        std::cerr << "vigs eval image: " << test << " is " << b.width << "x" << b.height << "x"
                  << b.channels << " but " << ref << " is " << a.width << "x" << a.height << "x"
                  << a.channels << "\n";
        exit_code.value = 1;
        return;
      }
      const auto w = mapping::parse_ssim_window(window);
      const auto q = mapping::image_quality(a, b, w);
      io::Json j;
      j["ref"] = ref;
      j["test"] = test;
      j["width"] = a.width;
      j["height"] = a.height;
      j["channels"] = a.channels;
      // Identical images have an unbounded PSNR: reported as null, as before.
      j["psnr_db"] = io::finite_or_null(io::rounded(q.psnr_db, 10).get<double>());
      j["ssim"] = io::finite_or_null(io::rounded(q.ssim, 10).get<double>());
      j["ssim_window"] = window;
      j["ssim_covariance"] = w == mapping::SsimWindow::kUniform7 ? "sample" : "population";
      j["ssim_border"] = "valid windows only";
      std::cout << io::json_line(j) << "\n";
    } catch (const std::exception& e) {
      std::cerr << "vigs eval image: " << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
