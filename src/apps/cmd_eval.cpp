// `vigs eval ate`, `vigs eval rpe` and `vigs eval run`: trajectory accuracy as JSON, and the
// report of a pipeline run.
#include <iostream>
#include <stdexcept>
#include <string>

#include "apps/commands.hpp"
#include "apps/eval_group.hpp"
#include "apps/finite_option.hpp"
#include "core/config/default_config.hpp"
#include "core/config/diagnostics.hpp"
#include "core/config/yaml_loader.hpp"
#include "core/geometry/body_from_camera.hpp"
#include "eval/ate.hpp"
#include "eval/mcap_trajectory.hpp"
#include "eval/report.hpp"
#include "eval/rpe.hpp"
#include "eval/trajectory_file.hpp"
#include "io/json_text.hpp"
#include "io/mcap/damage_object.hpp"
#include "io/output_guard.hpp"

namespace vigs::apps {
namespace {

struct EvalArgs {
  std::string gt, est, align = "se3", topic = std::string(io::topics::kBodyPose.name);
  double max_dt_s = 0.02;
  double delta = 1.0;
  std::string delta_unit = "frames";
  std::string results_dir, config_file, est_frame = "camera", est_name = "trajectory.tum";
  bool no_plots = false, no_render = false;
  bool gt_to_camera = false;
  int every = 5, threads = 2;
  double keyframe_tol_s = 0.005;
};

config::RobotConfig load_robot(const std::string& file) {
  return file.empty() ? config::load_config_text(config::default_config_text(),
                                                 std::string(config::kDefaultConfigName))
                      : config::load_config_file(file);
}

/// Ground truth as given, or (--gt-to-camera) moved from the body to the camera with T_b_c.
eval::Trajectory load_gt(const EvalArgs& a) {
  eval::Trajectory gt = eval::load_any_trajectory(a.gt, a.topic);
  if (a.gt_to_camera) {
    const geometry::Pose T_b_c = geometry::body_from_camera(load_robot(a.config_file).extrinsics);
    for (auto& p : gt.poses) p.T_w_x = p.T_w_x * T_b_c;
  }
  return gt;
}

/// The tool's JSON object with "input_damage": {"gt", "est"} added (null each when intact), and
/// a warning on stderr for each damaged recording: damage is never silent.
std::string with_input_damage(std::string json, const eval::Trajectory& gt,
                              const eval::Trajectory& est) {
  for (const eval::Trajectory* t : {&gt, &est}) {
    if (t->damage.damaged())
      std::cerr << "vigs eval: " << io::mcap::damage_warning(t->damage, eval::poses_used(*t))
                << "\n";
  }
  if (json.empty() || json.back() != '}') return json;
  json.pop_back();
  return json + ", \"input_damage\": " +
         io::json_line({{"gt", io::mcap::damage_object(gt.damage, eval::poses_used(gt))},
                        {"est", io::mcap::damage_object(est.damage, eval::poses_used(est))}}) +
         "}";
}

/// Runs `body`, turning input errors into a message on stderr and exit code 1.
template <class Body>
void guarded(ExitCode& exit_code, Body&& body) {
  try {
    body();
  } catch (const eval::TrajectoryFileError& e) {
    std::cerr << "vigs eval: " << e.what() << "\n";
    exit_code.value = 1;
  } catch (const config::ConfigError& e) {
    std::cerr << "vigs eval: " << e.what() << "\n";
    exit_code.value = 1;
  } catch (const std::exception& e) {
    std::cerr << "vigs eval: " << e.what() << "\n";
    exit_code.value = 1;
  }
}

void add_trajectory_options(CLI::App* c, EvalArgs& a) {
  c->add_option("--gt", a.gt, "ground truth: TUM or KITTI file, or a .mcap recording")->required();
  c->add_option("--est", a.est, "estimate: TUM or KITTI file")->required();
  c->add_option("--max-dt", a.max_dt_s, "association window, s (TUM: 0.02)")
      ->check(kFiniteNumber & CLI::PositiveNumber);
  c->add_option("--topic", a.topic, "PoseStamped topic when --gt is a .mcap file");
  c->add_flag("--gt-to-camera", a.gt_to_camera,
              "compare camera poses: ground truth T_w_b becomes T_w_b T_b_c (T_b_c from --config)");
  c->add_option("--config", a.config_file, "robot YAML for T_b_c (default: built-in)")
      ->check(CLI::ExistingFile);
}

}  // namespace

void add_eval_command(CLI::App& app, ExitCode& exit_code) {
  CLI::App* group = eval_group(app);
  static EvalArgs a;

  auto* ate = group->add_subcommand(
      "ate", "Absolute trajectory error (Umeyama alignment, TUM association) as JSON");
  add_trajectory_options(ate, a);
  ate->add_option("--align", a.align, "se3 | sim3 | none")
      ->check(CLI::IsMember({"se3", "sim3", "none"}));
  ate->callback([&exit_code] {
    guarded(exit_code, [] {
      eval::AteOptions opt;
      opt.align = eval::parse_alignment(a.align);
      opt.max_dt_s = a.max_dt_s;
      const auto gt = load_gt(a);
      const auto est = eval::load_any_trajectory(a.est, a.topic);
      std::cout << with_input_damage(eval::ate_json(eval::compute_ate(gt, est, opt), opt), gt, est)
                << "\n";
    });
  });

  auto* rpe = group->add_subcommand("rpe", "Relative pose error over a delta, as JSON");
  add_trajectory_options(rpe, a);
  rpe->add_option("--delta", a.delta, "pose distance: frames (whole number), metres or seconds")
      ->check(kFiniteNumber & CLI::PositiveNumber);
  rpe->add_option("--delta-unit", a.delta_unit, "frames | m | s")
      ->check(CLI::IsMember({"frames", "m", "s"}));
  rpe->add_option("--align", a.align, "none (or se3: same result) | sim3 (scale only)")
      ->check(CLI::IsMember({"se3", "sim3", "none"}));
  rpe->callback([&exit_code] {
    guarded(exit_code, [] {
      eval::RpeOptions opt;
      opt.delta = a.delta;
      opt.unit = a.delta_unit == "m"   ? eval::DeltaUnit::kMetres
                 : a.delta_unit == "s" ? eval::DeltaUnit::kSeconds
                                       : eval::DeltaUnit::kFrames;
      opt.max_dt_s = a.max_dt_s;
      opt.align = a.align == "sim3" ? eval::Alignment::kSim3 : eval::Alignment::kNone;
      const auto gt = load_gt(a);
      const auto est = eval::load_any_trajectory(a.est, a.topic);
      std::cout << with_input_damage(eval::rpe_json(eval::compute_rpe(gt, est, opt), opt), gt, est)
                << "\n";
    });
  });

  auto* run = group->add_subcommand(
      "run",
      "Write RESULTS_DIR/report.md (ATE, RPE, PSNR/SSIM, run statistics, plots) for a pipeline "
      "run");
  run->add_option("RESULTS_DIR", a.results_dir,
                  "folder with the run's trajectory.tum (and optionally map.ply, keyframes.txt, "
                  "stats.json)")
      ->required()
      ->check(CLI::ExistingDirectory);
  run->add_option("--gt", a.gt, "the recording (.mcap) the run was made on, or a TUM file")
      ->required()
      ->check(CLI::ExistingFile);
  run->add_option("--estimate", a.est_name, "estimate file name inside RESULTS_DIR");
  run->add_option("--estimate-frame", a.est_frame,
                  "camera: the estimate is T_w_c (ground truth moved by T_b_c); body: T_w_b")
      ->check(CLI::IsMember({"camera", "body"}));
  run->add_option("--config", a.config_file, "robot YAML for T_b_c (default: built-in)")
      ->check(CLI::ExistingFile);
  run->add_option("--align", a.align, "se3 | sim3 | none")
      ->check(CLI::IsMember({"se3", "sim3", "none"}));
  run->add_option("--max-dt", a.max_dt_s, "association window, s")
      ->check(kFiniteNumber & CLI::PositiveNumber);
  run->add_flag("--no-plots", a.no_plots, "skip the gnuplot PNGs");
  run->add_flag("--no-render", a.no_render, "skip PSNR/SSIM and the rendered views");
  run->add_option("--every", a.every, "frame stride of the PSNR/SSIM sets")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  run->add_option("--keyframe-tol", a.keyframe_tol_s,
                  "a frame this close (s) to a keyframes.txt stamp is that keyframe")
      ->check(kFiniteNumber & CLI::PositiveNumber)
      ->capture_default_str();
  run->add_option("--threads", a.threads, "rasterizer threads")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  run->callback([&exit_code] {
    guarded(exit_code, [] {
      io::refuse_output_over_inputs(a.results_dir + "/report.md", {a.gt, a.config_file});
      const auto cfg = load_robot(a.config_file);
      eval::ReportOptions opt;
      opt.results_dir = a.results_dir;
      opt.gt_path = a.gt;
      opt.estimate_name = a.est_name;
      opt.estimate_is_camera = a.est_frame == "camera";
      opt.T_b_c = geometry::body_from_camera(cfg.extrinsics);
      opt.ate.align = eval::parse_alignment(a.align);
      opt.ate.max_dt_s = a.max_dt_s;
      opt.plots = !a.no_plots;
      opt.render = !a.no_render;
      opt.quality.every = a.every;
      opt.quality.keyframe_tol_s = a.keyframe_tol_s;
      opt.quality.max_dt_s = a.max_dt_s;
      opt.quality.threads = a.threads;
      const auto r = eval::write_report(opt);
      for (const auto& w : r.warnings) std::cerr << "vigs eval run: " << w << "\n";
      std::cout << eval::report_json(r, opt) << "\n";
    });
  });
}

}  // namespace vigs::apps
