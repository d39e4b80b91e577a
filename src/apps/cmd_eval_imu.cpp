// `vigs eval imu --imu imu0.csv --gt groundtruth.csv --window SECONDS [--bias gt|zero]`:
// preintegrates every window of a EuRoC-format recording and prints, as JSON, the rotation,
// velocity and position error against the ground truth (see inertial/imu_window_eval.hpp).
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "apps/commands.hpp"
#include "apps/eval_group.hpp"
#include "apps/finite_option.hpp"
#include "core/config/default_config.hpp"
#include "core/config/diagnostics.hpp"
#include "core/config/yaml_loader.hpp"
#include "inertial/euroc_csv.hpp"
#include "inertial/imu_window_eval.hpp"
#include "io/json_text.hpp"

namespace vigs::apps {

namespace {

struct EvalImuArgs {
  std::string imu_csv;
  std::string gt_csv;
  double window_s = 1.0;
  std::string bias = "gt";
  std::string scheme;  // empty: the configuration's inertial.scheme
  std::string config_file;
};

// Figures keep the report's established 9 significant digits.
io::Json num9(double v) {
  return io::rounded(v, 9);
}

io::Json json_stats(const inertial::ErrorStats& s) {
  return {{"rms", num9(s.rms)}, {"max", num9(s.max)}};
}

int run_eval_imu(const EvalImuArgs& a) {
  const config::RobotConfig cfg =
      a.config_file.empty() ? config::load_config_text(config::default_config_text(),
                                                       std::string(config::kDefaultConfigName))
                            : config::load_config_file(a.config_file);
  inertial::WindowEvalOptions o;
  o.window_s = a.window_s;
  o.bias = a.bias == "zero" ? inertial::BiasSource::kZero : inertial::BiasSource::kGroundTruth;
  const std::string scheme = a.scheme.empty() ? cfg.inertial.scheme : a.scheme;
  if (!inertial::parse_integration_scheme(scheme, o.scheme)) {
    throw std::invalid_argument("unknown integration scheme '" + scheme + "'");
  }
  o.noise = inertial::ImuNoise::from(cfg.imu);
  o.gravity_mps2 = cfg.imu.gravity_mps2;

  const auto imu = inertial::read_euroc_imu_csv(a.imu_csv);
  const auto gt = inertial::read_euroc_groundtruth_csv(a.gt_csv);
  const inertial::WindowEvalResult r = inertial::evaluate_imu_windows(imu, gt, o);

  io::Json j;
  j["imu"] = a.imu_csv;
  j["gt"] = a.gt_csv;
  j["window_s"] = num9(a.window_s);
  j["bias"] = a.bias;
  j["scheme"] = std::string(inertial::integration_scheme_name(o.scheme));
  j["gravity_mps2"] = num9(o.gravity_mps2);
  j["windows"] = r.windows;
  j["skipped_gap"] = r.skipped_gap;
  j["mean_window_s"] = num9(r.mean_window_s);
  j["rotation_deg"] = json_stats(r.rotation_deg);
  j["velocity_mps"] = json_stats(r.velocity_mps);
  j["position_m"] = json_stats(r.position_m);
  j["predicted_sigma"] = {{"rotation_deg", num9(r.sigma_rotation_deg)},
                          {"velocity_mps", num9(r.sigma_velocity_mps)},
                          {"position_m", num9(r.sigma_position_m)}};
  std::cout << io::json_lines(j) << "\n";
  return 0;
}

}  // namespace

void add_eval_imu_command(CLI::App& app, ExitCode& exit_code) {
  static EvalImuArgs args;
  CLI::App* imu = eval_group(app)->add_subcommand(
      "imu",
      "Preintegrate every window of a EuRoC-format IMU CSV and print, as JSON, the rotation "
      "(deg), velocity (m/s) and position (m) RMS and max error against the ground truth");
  imu->add_option("--imu", args.imu_csv, "IMU CSV: t[ns], w xyz [rad/s], a xyz [m/s^2]")
      ->required();
  imu->add_option("--gt", args.gt_csv,
                  "ground-truth CSV: t[ns], p xyz, q w x y z, v xyz, b_w xyz, b_a xyz (body = "
                  "IMU frame in a z-up world)")
      ->required();
  imu->add_option("--window", args.window_s, "window length, s")
      ->check(kFiniteNumber)
      ->check(CLI::Range(1e-3, 3600.0))
      ->capture_default_str();
  imu->add_option("--bias", args.bias, "biases: gt (ground truth at each window start) or zero")
      ->check(CLI::IsMember({"gt", "zero"}))
      ->capture_default_str();
  imu->add_option("--scheme", args.scheme,
                  "integration scheme: midpoint or zoh (default: the configuration's)")
      ->check(CLI::IsMember({"midpoint", "zoh"}));
  imu->add_option("--config", args.config_file,
                  "robot YAML for gravity and noise densities (default: built-in)")
      ->check(CLI::ExistingFile);
  imu->callback([&exit_code] {
    try {
      exit_code.value = run_eval_imu(args);
    } catch (const config::ConfigError& e) {
      std::cerr << e.what() << "\n";
      exit_code.value = 1;
    } catch (const std::exception& e) {
      std::cerr << "vigs eval imu: " << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
