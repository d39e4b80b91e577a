// `vigs align`: register one RGB-D frame (source) to another (target) with GICP and print the
// relative pose as JSON. Users debug camera setups with it.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/commands.hpp"
#include "apps/finite_option.hpp"
#include "core/config/yaml_loader.hpp"
#include "io/image_io.hpp"
#include "io/json_text.hpp"
#include "tracking/camera_file.hpp"
#include "tracking/gicp.hpp"
#include "tracking/preprocess.hpp"
#include "tracking/settings_from_config.hpp"

namespace vigs::apps {

namespace {

struct AlignOptions {
  std::string camera_file;
  std::vector<std::string> source;  // colour, depth
  std::vector<std::string> target;
  double depth_scale = 1000.0;  // raw 16-bit units per metre
  std::vector<double> init;     // x y z qx qy qz qw
  std::string config_file;
  int pixel_stride = 0;  // 0 = from config
  int num_threads = 0;
};

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The report's figures keep 9 significant digits (its established precision).
io::Json num9(double v) {
  return io::rounded(v, 9);
}

io::Json num9_array(const double* v, int n) {
  io::Json a = io::Json::array();
  for (int i = 0; i < n; ++i) a.push_back(num9(v[i]));
  return a;
}

int run_align(const AlignOptions& o) {
  const auto t_start = Clock::now();
  const PinholeCamera camera = tracking::load_camera_file(o.camera_file);
  config::TrackingSettings ts;
  if (!o.config_file.empty()) ts = config::load_config_file(o.config_file).tracking;
  if (o.pixel_stride > 0) ts.preprocess.depth.pixel_stride = o.pixel_stride;
  if (o.num_threads > 0) ts.gicp.num_threads = o.num_threads;

  geometry::Pose T_init = geometry::Pose::Identity();
  if (!o.init.empty()) {
    if (o.init.size() != 7) {
      std::cerr << "--init: expected 7 numbers x,y,z,qx,qy,qz,qw, got " << o.init.size() << "\n";
      return 1;
    }
    const Eigen::Quaterniond q(o.init[6], o.init[3], o.init[4], o.init[5]);
    if (q.norm() < 1e-9) {
      std::cerr << "--init: quaternion has zero norm\n";
      return 1;
    }
    T_init = geometry::make_pose(Eigen::Vector3d(o.init[0], o.init[1], o.init[2]), q);
  }

  const auto t_load = Clock::now();
  const double depth_scale_m = 1.0 / o.depth_scale;
  const ImageU8 src_rgb = io::read_rgb(o.source[0]);
  const ImageF32 src_depth = io::read_depth_m(o.source[1], depth_scale_m);
  const ImageU8 tgt_rgb = io::read_rgb(o.target[0]);
  const ImageF32 tgt_depth = io::read_depth_m(o.target[1], depth_scale_m);
  const double load_ms = ms_since(t_load);

  vigs::rt::WorkerTeam team(ts.gicp.num_threads);
  tracking::FramePreprocessor pre(camera, ts.preprocess, team);
  tracking::GaussianCloud src, tgt;
  tracking::KdTree tgt_tree;
  tracking::PixelGrid tgt_grid;
  const auto t_pre = Clock::now();
  const auto process = [&pre](const ImageF32& depth, const ImageU8& rgb,
                              const std::vector<std::string>& files, tracking::GaussianCloud& cloud,
                              tracking::KdTree* tree, tracking::PixelGrid* grid) {
    try {
      return tree != nullptr ? pre.process(depth, rgb, cloud, *tree, grid)
                             : pre.process(depth, rgb, cloud);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(files[0] + ", " + files[1] + ": " + e.what());
    }
  };
  const auto src_stats = process(src_depth, src_rgb, o.source, src, nullptr, nullptr);
  const auto tgt_stats = process(tgt_depth, tgt_rgb, o.target, tgt, &tgt_tree, &tgt_grid);
  const double pre_ms = ms_since(t_pre);

  tracking::Gicp gicp(ts.gicp);
  const auto t_align = Clock::now();
  const tracking::GicpResult r =
      gicp.align(tracking::CloudTarget{&tgt, &tgt_tree, &tgt_grid}, src, T_init);
  const double align_ms = ms_since(t_align);

  const Eigen::Quaterniond q(r.T_t_s.linear());
  const Eigen::Vector3d t = r.T_t_s.translation();
  const double tq[7] = {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
  Eigen::Matrix<double, 4, 4, Eigen::RowMajor> m = r.T_t_s.matrix();
  Eigen::Matrix<double, 6, 6, Eigen::RowMajor> info = r.information;
  io::Json js;
  js["source"] = o.source;
  js["target"] = o.target;
  js["pose_convention"] = "T_target_source: p_target = R * p_source + t (camera frames)";
  js["T_target_source"] = {{"translation_m", num9_array(tq, 3)},
                           {"quaternion_xyzw", num9_array(tq + 3, 4)},
                           {"matrix_row_major", num9_array(m.data(), 16)}};
  js["tum_xyz_qxyzw"] = num9_array(tq, 7);
  js["verdict"] = std::string(tracking::to_string(r.verdict));
  js["iterations"] = r.iterations;
  js["inlier_ratio"] = num9(r.inlier_ratio);
  js["overlap_ratio"] = num9(r.overlap_ratio);
  js["eigen_ratio"] = num9(r.eigen_ratio);
  js["information_row_major"] = num9_array(info.data(), 36);
  js["points"] = {{"source", src_stats.points},
                  {"target", tgt_stats.points},
                  {"source_invalid", src_stats.invalid},
                  {"source_out_of_range", src_stats.too_near + src_stats.too_far}};
  js["time_ms"] = {{"load", num9(load_ms)},
                   {"preprocess", num9(pre_ms)},
                   {"align", num9(align_ms)},
                   {"total", num9(ms_since(t_start))}};
  std::cout << io::json_lines(js) << "\n";
  return r.verdict == tracking::GicpVerdict::converged ? 0 : 3;
}

}  // namespace

void add_align_command(CLI::App& app, ExitCode& exit_code) {
  static AlignOptions o;
  auto* cmd = app.add_subcommand(
      "align",
      "Register a source RGB-D frame to a target frame with GICP; prints JSON with T_target_source "
      "(maps source-camera points into the target camera frame), iterations, inlier ratio, "
      "verdict and times. Exit code 0 = converged, 3 = not converged / degenerate / diverged, "
      "1 = bad input.");
  cmd->add_option("--camera", o.camera_file,
                  "camera file: YAML {fx, fy, cx, cy, width, height}, Kimera sensor YAML "
                  "(intrinsics, resolution) or Open3D intrinsic JSON")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--source", o.source, "COLOR,DEPTH of the source frame (PNG/JPEG, PNG16/TIFF)")
      ->required()
      ->delimiter(',')
      ->expected(2);
  cmd->add_option("--target", o.target, "COLOR,DEPTH of the target frame")
      ->required()
      ->delimiter(',')
      ->expected(2);
  cmd->add_option("--depth-scale", o.depth_scale,
                  "16-bit depth units per metre (1000 = millimetres); float TIFF is metres")
      ->check(kFiniteNumber & CLI::PositiveNumber);
  cmd->add_option("--init", o.init, "initial T_target_source as x,y,z,qx,qy,qz,qw")
      ->delimiter(',')
      ->check(kFiniteNumber);
  cmd->add_option("--config", o.config_file, "robot YAML whose tracking: section to use")
      ->check(CLI::ExistingFile);
  cmd->add_option("--stride", o.pixel_stride, "pixel stride (overrides the config)")
      ->check(CLI::Range(1, 64));
  cmd->add_option("--threads", o.num_threads, "worker threads (overrides the config)")
      ->check(CLI::Range(1, 64));
  cmd->callback([&exit_code] {
    try {
      exit_code.value = run_align(o);
    } catch (const std::exception& e) {
      std::cerr << "vigs align: " << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
