#pragma once
#include <string>

#include "core/config/visitor.hpp"

namespace vigs::config {

/// `vigs simulate`: the synthetic uHumans-like sequence. Camera intrinsics and rate come from
/// CameraSettings, IMU rate and noise densities from ImuSettings, T_b_c from
/// ExtrinsicsSettings. Command-line options override preset, humans, seconds, seed and gray.
struct SimSettings {
  std::string preset = "office";  ///< office (64 m x 64 m) | apartment (24 m x 24 m)
  int humans = 12;                ///< walking people (uHumans: 0, 12, 24, 60)
  double seconds = 120.0;         ///< sequence length; 0 = the whole route
  int seed = 1;
  bool gray = false;                     ///< mono8 images (uHumansV1) instead of rgb8
  std::string depth_encoding = "16UC1";  ///< 16UC1 (mm) | 32FC1 (m)
  double depth_noise_base_m = 0.0005;
  double depth_noise_quadratic_per_m = 0.0015;
  double hole_incidence_cos = 0.12;
  double dropout_incidence_cos = 0.25;
  double rgb_noise_sigma = 1.0;
  /// Carrier motion: smooth (B-spline route, steady speed) | realistic (stop-and-go, quick
  /// turns at corners, walking bob, vibration; sim/realistic_motion.hpp).
  std::string motion = "smooth";
  double speed_mps = 1.2;        ///< cruise speed (control point spacing per knot interval)
  double camera_height_m = 1.3;  ///< body height above the floor
  int render_threads = 2;

  void visit(Visitor& v) {
    v.field("preset", preset, {"office", "apartment"}, "floor plan");
    v.field("humans", humans, {"-", 0, 500, "number of walking people"});
    v.field("seconds", seconds, {"s", 0.0, 36000.0, "sequence length; 0 = whole route"});
    v.field("seed", seed, {"-", 0, 2147483647, "random seed (layout, people, noise)"});
    v.field("gray", gray, "write mono8 instead of rgb8 images");
    v.field("depth_encoding", depth_encoding, {"16UC1", "32FC1"},
            "depth image encoding: 16UC1 millimetres or 32FC1 metres");
    v.field("depth_noise_base_m", depth_noise_base_m,
            {"m", 0.0, 0.1, "depth noise sigma at zero range"});
    v.field("depth_noise_quadratic_per_m", depth_noise_quadratic_per_m,
            {"1/m", 0.0, 0.1, "depth noise sigma growth: sigma = base + k z^2"});
    v.field("hole_incidence_cos", hole_incidence_cos,
            {"-", 0.0, 1.0, "depth missing below this cosine of incidence"});
    v.field("dropout_incidence_cos", dropout_incidence_cos,
            {"-", 0.0, 1.0, "depth missing with rising probability below this cosine"});
    v.field("rgb_noise_sigma", rgb_noise_sigma, {"grey levels", 0.0, 50.0, "image noise"});
    v.field("motion", motion, {"smooth", "realistic"},
            "carrier motion: smooth B-spline route, or realistic (stop-and-go, quick turns, "
            "walking bob, vibration)");
    v.field("speed_mps", speed_mps, {"m/s", 0.1, 1.5, "cruise speed along the route"});
    v.field("camera_height_m", camera_height_m, {"m", 0.3, 2.0, "body height above floor"});
    v.field("render_threads", render_threads, {"-", 1, 64, "ray-casting threads"});
    v.require(dropout_incidence_cos >= hole_incidence_cos, "dropout_incidence_cos",
              "must be >= hole_incidence_cos");
  }
};

}  // namespace vigs::config
