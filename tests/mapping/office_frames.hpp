#pragma once
// The simulated office at 360x240, shared by the mapping tests that insert real-looking frames:
// at stride 2 its samples are as far apart as 720x480's at the tracker's stride 4.
#include <algorithm>
#include <cmath>

#include "../common/scaled_camera.hpp"
#include "core/config/robot_config.hpp"
#include "mapping/rasterizer.hpp"
#include "sim/simulator.hpp"

namespace vigs::mapping::test {

/// The office route without people, `seconds` long, at 360x240.
inline config::RobotConfig half_res_office(double seconds) {
  config::RobotConfig cfg;
  vigs::test::use_default_camera_divided(cfg.camera, 2);
  cfg.sim.preset = "office";
  cfg.sim.humans = 0;
  cfg.sim.seconds = seconds;
  return cfg;
}

struct Psnr {
  double whole_db = 0, valid_depth_db = 0;
};

/// PSNR (8-bit, peak 255) of the render against the frame over every pixel and over the
/// pixels with a depth measurement.
inline Psnr psnr_of(const RenderResult<float>& r, const sim::RgbdFrame& f) {
  double se_all = 0, se_valid = 0;
  std::size_t n_valid = 0;
  const std::size_t np = f.depth_m.size();
  for (std::size_t p = 0; p < np; ++p) {
    double se = 0;
    for (int c = 0; c < 3; ++c) {
      const double v = std::round(255.0 * std::clamp(r.color[3 * p + c], 0.0f, 1.0f));
      const double d = v - f.color[3 * p + c];
      se += d * d;
    }
    se_all += se;
    if (f.depth_m[p] > 0) {
      se_valid += se;
      ++n_valid;
    }
  }
  const auto db = [](double se, double n) { return 10.0 * std::log10(255.0 * 255.0 / (se / n)); };
  return {db(se_all, 3.0 * static_cast<double>(np)),
          db(se_valid, 3.0 * static_cast<double>(n_valid))};
}

}  // namespace vigs::mapping::test
