#include "eval/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <limits>
#include <optional>
#include <stdexcept>

#include "eval/gnuplot.hpp"
#include "eval/mcap_trajectory.hpp"
#include "eval/trajectory_file.hpp"
#include "io/atomic_file.hpp"
#include "io/json_text.hpp"
#include "io/mcap/damage_object.hpp"
#include "mapping/ply_io.hpp"

namespace vigs::eval {
namespace fs = std::filesystem;
namespace {

void write_text(const std::string& path, const std::string& text) {
  io::write_file_atomically(path, [&](std::FILE* f) {
    if (std::fwrite(text.data(), 1, text.size(), f) != text.size()) {
      throw std::runtime_error(path + ": write failed");
    }
  });
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string stats_row(const std::string& name, const ErrorStats& s, const char* f) {
  return "| " + name + " | " + std::to_string(s.count) + " | " + fmt(f, s.rmse) + " | " +
         fmt(f, s.mean) + " | " + fmt(f, s.median) + " | " + fmt(f, s.std) + " | " + fmt(f, s.min) +
         " | " + fmt(f, s.max) + " |\n";
}

/// Data files and a gnuplot script; PNGs are rendered to temporary names and renamed.
std::vector<std::string> draw_plots(const ReportOptions& opt, const ReportResult& r,
                                    std::vector<std::string>& warnings) {
  const fs::path dir = fs::path(opt.results_dir) / "plots";
  fs::create_directories(dir);
  const double t0 = r.ate.t_s.empty() ? 0.0 : r.ate.t_s.front();
  // Top view: the two axes along which the ground truth spreads most (x-y for z-up worlds,
  // x-z for camera-convention worlds such as KITTI).
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& p : r.ate.p_gt_m) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Eigen::Vector3d extent = hi - lo;
  int drop = 0;
  extent.minCoeff(&drop);
  const int ax = drop == 0 ? 1 : 0, ay = drop == 2 ? 1 : 2;
  const char* names = "xyz";
  std::string top, err;
  for (std::size_t i = 0; i < r.ate.pairs; ++i) {
    char line[160];
    std::snprintf(line, sizeof line, "%.6f %.6f %.6f %.6f\n", r.ate.p_gt_m[i][ax],
                  r.ate.p_gt_m[i][ay], r.ate.p_est_m[i][ax], r.ate.p_est_m[i][ay]);
    top += line;
    std::snprintf(line, sizeof line, "%.6f %.6f\n", r.ate.t_s[i] - t0, r.ate.error_m[i]);
    err += line;
  }
  write_text((dir / "trajectory_top.dat").string(), top);
  write_text((dir / "ate_over_time.dat").string(), err);
  const std::string top_png = (dir / "trajectory_top.png").string();
  const std::string err_png = (dir / "ate_over_time.png").string();
  // The script names its files relative to its own folder and gnuplot runs there, so it
  // still draws them after a staging folder is renamed into place (`cd plots; gnuplot
  // plots.gp`).
  std::string script =
      std::string(
          "set terminal pngcairo size 900,800 font 'sans,11'\n"
          "set output 'trajectory_top.png.tmp'\n"
          "set title 'Trajectory, top view (estimate aligned ") +
      alignment_name(opt.ate.align) + ")'\nset xlabel '" + names[ax] + " [m]'\nset ylabel '" +
      names[ay] +
      " [m]'\nset size ratio -1\nset grid\nset key outside "
      "bottom center horizontal\n"
      "plot 'trajectory_top.dat' using 1:2 with lines lw 2 lc rgb '#303030' title 'ground truth', "
      "'' using 3:4 with "
      "lines lw 1.5 lc rgb '#d03020' title 'estimate'\n"
      "set output\n"
      "set terminal pngcairo size 1000,450 font 'sans,11'\n"
      "set output 'ate_over_time.png.tmp'\n"
      "set size noratio\nset title 'Absolute trajectory error over time (RMSE " +
      fmt("%.4f", r.ate.stats.rmse) +
      " m)'\nset xlabel 'time [s]'\nset ylabel 'error [m]'\nset key off\n"
      "plot 'ate_over_time.dat' using 1:2 with lines lc rgb '#2060c0'\n"
      "set output\n";
  const std::string script_path = (dir / "plots.gp").string();
  write_text(script_path, script);
  const std::string why = run_gnuplot(script_path, (dir / "gnuplot.log").string(), dir.string());
  if (!why.empty()) {
    warnings.push_back("plots not drawn: " + why);
    return {};
  }
  std::vector<std::string> out;
  for (const auto& png : {top_png, err_png}) {
    std::error_code ec;
    fs::rename(png + ".tmp", png, ec);
    if (ec) {
      warnings.push_back("plot " + png + " not written: " + ec.message());
    } else {
      out.push_back(png);
    }
  }
  return out;
}

bool is_mcap_path(const std::string& p) {
  return p.size() >= 5 && p.compare(p.size() - 5, 5, ".mcap") == 0;
}

std::string opt_num(const std::optional<double>& v, const char* f) {
  return v ? fmt(f, *v) : std::string("not measured");
}

/// Reads the optional RESULTS_DIR files, renders the map when it can, and returns the
/// markdown of the rendering and statistics sections plus the "not measured" items.
/// `gt`: the ground truth as write_report holds it (camera poses when the estimate is of the
/// camera, body poses otherwise).
void measure_map_and_run(const ReportOptions& opt, const Trajectory& est, const Trajectory& gt,
                         ReportResult& r, std::string& md_sections,
                         std::vector<std::string>& not_measured) {
  const fs::path dir(opt.results_dir);
  const bool have_map = fs::exists(dir / pipeline::kMapFile);
  const bool have_kf = fs::exists(dir / pipeline::kKeyframesFile);
  const bool have_stats = fs::exists(dir / pipeline::kStatsFile);
  for (const auto& [have, name] :
       {std::pair{have_map, pipeline::kMapFile}, std::pair{have_kf, pipeline::kKeyframesFile},
        std::pair{have_stats, pipeline::kStatsFile}})
    if (!have) r.missing.emplace_back(name);
  r.have_keyframes = have_kf;
  if (have_kf)
    r.keyframe_t_s = pipeline::read_keyframe_times((dir / pipeline::kKeyframesFile).string());
  if (have_stats) r.run_stats = pipeline::read_run_stats((dir / pipeline::kStatsFile).string());
  mapping::GaussianMap map;
  if (have_map) {
    map = mapping::read_gaussian_ply((dir / pipeline::kMapFile).string());
    r.gaussians = static_cast<long>(map.size());
  }
  const bool mcap = is_mcap_path(opt.gt_path);
  if (opt.render && have_map && mcap) {
    // The map is rendered at the poses it was built at: the estimate's, or the ground truth's
    // for a map built at them (the ground truth's world frame, not the estimate's).
    r.rendered_at_ground_truth = r.run_stats.map_poses == "ground_truth";
    Trajectory cam = r.rendered_at_ground_truth ? gt : est;
    if (r.rendered_at_ground_truth) {
      // Only the frames the run processed: the recording's ground truth runs on past a run cut
      // short (replay --frames), where the map holds nothing.
      double t_first_s = std::numeric_limits<double>::infinity();
      double t_last_s = -t_first_s;
      for (const TimedPose& p : est.poses) {
        t_first_s = std::min(t_first_s, p.t_s);
        t_last_s = std::max(t_last_s, p.t_s);
      }
      const double dt_s = opt.quality.max_dt_s;
      std::erase_if(cam.poses, [&](const TimedPose& p) {
        return p.t_s < t_first_s - dt_s || p.t_s > t_last_s + dt_s;
      });
    }
    if (!opt.estimate_is_camera)  // then both are of the body
      for (auto& p : cam.poses) p.T_w_x = p.T_w_x * opt.T_b_c;
    std::stable_sort(cam.poses.begin(), cam.poses.end(),
                     [](const TimedPose& a, const TimedPose& b) { return a.t_s < b.t_s; });
    RenderQualityOptions q = opt.quality;
    fs::create_directories(dir / "plots");
    q.side_by_side_png = (dir / "plots" / "rendered_vs_recorded.png").string();
    r.quality =
        measure_render_quality(map, cam, have_kf ? &r.keyframe_t_s : nullptr, opt.gt_path, q);
    r.quality_measured = true;
    md_sections += render_quality_markdown(r.quality, q, have_kf, "plots/rendered_vs_recorded.png",
                                           r.rendered_at_ground_truth);
    if (!have_kf)
      not_measured.push_back(
          "**PSNR and SSIM on held-out frames**: no keyframes.txt in the results, so frames "
          "never used as keyframes cannot be told apart.");
  } else {
    const std::string why = !opt.render ? "rendering was switched off (--no-render)"
                            : !have_map ? "the results hold no map.ply"
                                        : "the ground truth is not an MCAP recording, so there "
                                          "are no recorded images to compare with";
    not_measured.push_back("**PSNR and SSIM** (every " + std::to_string(opt.quality.every) +
                           "th frame and held-out frames) and the **rendered views beside the "
                           "recording**: " +
                           why + ".");
  }
  md_sections += "## Map and run statistics\n\n| quantity | value | source |\n|---|---|---|\n";
  md_sections += "| Gaussians in the map | " +
                 (have_map ? std::to_string(r.gaussians) : std::string("not measured")) +
                 " | map.ply |\n";
  const pipeline::RunStats& st = r.run_stats;
  std::optional<double> fps = st.fps;
  std::string fps_source = "stats.json fps";
  if (!fps && st.frames && st.wall_s && *st.wall_s > 0) {
    fps = *st.frames / *st.wall_s;
    fps_source = "stats.json frames / wall_s";
  }
  std::optional<double> peak_mib;
  if (st.peak_rss_bytes) peak_mib = *st.peak_rss_bytes / (1024.0 * 1024.0);
  md_sections += "| frames processed | " + opt_num(st.frames, "%.0f") + " | stats.json |\n";
  md_sections += "| wall time [s] | " + opt_num(st.wall_s, "%.3f") + " | stats.json |\n";
  md_sections += "| frames per second | " + opt_num(fps, "%.2f") + " | " + fps_source + " |\n";
  md_sections += "| peak memory (RSS) [MiB] | " + opt_num(peak_mib, "%.1f") +
                 " | stats.json peak_rss_bytes |\n";
  md_sections +=
      "| Gaussians reported by the run | " + opt_num(st.gaussians, "%.0f") + " | stats.json |\n\n";
  if (!have_map) not_measured.push_back("**Gaussian count**: the results hold no map.ply.");
  if (!fps)
    not_measured.push_back("**Frames per second**: " +
                           std::string(have_stats
                                           ? "stats.json has neither fps nor frames and wall_s."
                                           : "the results hold no stats.json."));
  if (!peak_mib)
    not_measured.push_back("**Peak memory**: " +
                           std::string(have_stats ? "stats.json has no peak_rss_bytes."
                                                  : "the results hold no stats.json."));
}

}  // namespace

ReportResult write_report(const ReportOptions& opt) {
  if (!fs::is_directory(opt.results_dir)) {
    throw std::invalid_argument(opt.results_dir + ": not a results directory");
  }
  Trajectory gt = load_any_trajectory(opt.gt_path);
  if (opt.estimate_is_camera) {
    for (auto& p : gt.poses) p.T_w_x = p.T_w_x * opt.T_b_c;
  }
  const std::string est_path = (fs::path(opt.results_dir) / opt.estimate_name).string();
  if (!fs::exists(est_path)) {
    throw std::invalid_argument(est_path + ": no estimated trajectory (TUM file) in the results");
  }
  const Trajectory est = load_trajectory_file(est_path);
  ReportResult r;
  r.input_damage = gt.damage;
  if (gt.damage.damaged()) {
    r.input_damage_used = poses_used(gt);
    r.warnings.push_back(io::mcap::damage_warning(gt.damage, r.input_damage_used));
  }
  r.ate = compute_ate(gt, est, opt.ate);
  RpeOptions rf;
  rf.max_dt_s = opt.ate.max_dt_s;
  rf.align = opt.ate.align == Alignment::kSim3 ? Alignment::kSim3 : Alignment::kNone;
  r.rpe_frame = compute_rpe(gt, est, rf);
  RpeOptions rm = rf;
  rm.unit = DeltaUnit::kMetres;
  rm.delta = opt.rpe_delta_m;
  try {
    r.rpe_metre = compute_rpe(gt, est, rm);
  } catch (const std::invalid_argument& e) {
    r.warnings.push_back(std::string("RPE over ") + fmt("%.2f", opt.rpe_delta_m) +
                         " m not computed: " + e.what());
  }
  if (opt.plots) r.plots = draw_plots(opt, r, r.warnings);
  std::string map_sections;
  std::vector<std::string> not_measured;
  // The map follows the loop closer as trajectory.tum does (results_dir.hpp): views are
  // rendered at the estimate's poses.
  measure_map_and_run(opt, est, gt, r, map_sections, not_measured);
  if (r.quality_measured && r.quality.damage.damaged() && !r.input_damage.damaged()) {
    r.input_damage = r.quality.damage;
    r.input_damage_used = std::to_string(r.quality.recorded_frames) + " recorded frames";
    r.warnings.push_back(io::mcap::damage_warning(r.input_damage, r.input_damage_used));
  }

  std::string md = "# VIGS evaluation report\n\n";
  const std::string shown_dir = opt.shown_dir.empty() ? opt.results_dir : opt.shown_dir;
  md += "- results: `" + shown_dir + "`\n- estimate: `" +
        (fs::path(shown_dir) / opt.estimate_name).string() + "` (" +
        (opt.estimate_is_camera ? "camera poses T_w_c; ground truth body poses moved to the "
                                  "camera with T_b_c"
                                : "body poses T_w_b") +
        ")\n- ground truth: `" + opt.gt_path + "`\n";
  md += "- association: TUM greedy unique matching, |dt| < " + fmt("%.4g", opt.ate.max_dt_s) +
        " s; " + std::to_string(r.ate.pairs) + " of " + std::to_string(est.poses.size()) +
        " estimated poses matched\n";
  md += "- alignment: " + std::string(alignment_name(opt.ate.align)) + " (Umeyama on positions)" +
        (opt.ate.align == Alignment::kSim3 ? ", scale " + fmt("%.6f", r.ate.alignment.s) : "") +
        "\n\n";
  md += "## Absolute trajectory error (m)\n\n";
  md +=
      "RMSE is the root mean square of the per-pose errors. GS-ICP SLAM and SplaTAM print the "
      "*mean* under the name \"ATE RMSE\"; compare their figures with the mean column.\n\n";
  md +=
      "| metric | pairs | rmse | mean | median | std | min | max "
      "|\n|---|---|---|---|---|---|---|---|\n";
  md += stats_row("ATE translation [m]", r.ate.stats, "%.4f");
  md += "\n## Relative pose error\n\n";
  md +=
      "| metric | pairs | rmse | mean | median | std | min | max "
      "|\n|---|---|---|---|---|---|---|---|\n";
  md += stats_row("RPE translation per frame [m]", r.rpe_frame.translation_m, "%.4f");
  md += stats_row("RPE rotation per frame [deg]", r.rpe_frame.rotation_deg, "%.4f");
  if (r.rpe_metre.pairs > 0) {
    md += stats_row("RPE translation per " + fmt("%.2g", opt.rpe_delta_m) + " m [m]",
                    r.rpe_metre.translation_m, "%.4f");
    md += stats_row("RPE rotation per " + fmt("%.2g", opt.rpe_delta_m) + " m [deg]",
                    r.rpe_metre.rotation_deg, "%.4f");
  }
  md += "\n## Plots\n\n";
  for (const auto& p : r.plots) {
    md +=
        "![" + fs::path(p).stem().string() + "](plots/" + fs::path(p).filename().string() + ")\n\n";
  }
  if (r.plots.empty()) md += "No plots were drawn (see the notes below).\n\n";
  md += map_sections;
  md += "## Not measured in this report\n\n";
  for (const auto& n : not_measured) md += "- " + n + "\n";
  md +=
      "- **LPIPS** needs pretrained network weights (AlexNet/VGG) that cannot be fetched on "
      "this machine, so it is not reported.\n";
  if (!r.missing.empty()) {
    md += "- Optional results files absent:";
    for (const auto& m : r.missing) md += " `" + m + "`";
    md += ".\n";
  }
  for (const auto& w : r.warnings) md += "- Note: " + w + "\n";
  r.report_path = (fs::path(opt.results_dir) / "report.md").string();
  write_text(r.report_path, md);
  return r;
}

std::string report_json(const ReportResult& r, const ReportOptions& opt) {
  RpeOptions rf;
  rf.max_dt_s = opt.ate.max_dt_s;
  rf.align = opt.ate.align == Alignment::kSim3 ? Alignment::kSim3 : Alignment::kNone;
  io::Json j;
  j["report"] = r.report_path;
  j["ate"] = ate_to_json(r.ate, opt.ate);
  j["rpe_frame"] = rpe_to_json(r.rpe_frame, rf);
  if (r.rpe_metre.pairs > 0) {
    RpeOptions rm = rf;
    rm.unit = DeltaUnit::kMetres;
    rm.delta = opt.rpe_delta_m;
    j["rpe_metre"] = rpe_to_json(r.rpe_metre, rm);
  }
  // Means over an empty set (no frame with depth) are NaN: stated as null, i.e. not measured.
  const auto set_json = [](const QualitySet& q) {
    io::Json s;
    s["frames"] = q.frames();
    s["psnr_db"] = io::finite_or_null(q.mean_psnr_db());
    s["ssim"] = io::finite_or_null(q.mean_ssim());
    s["frames_with_depth"] = q.frames_with_depth();
    s["psnr_valid_depth_db"] = io::finite_or_null(q.mean_psnr_valid_depth_db());
    s["ssim_valid_depth"] = io::finite_or_null(q.mean_ssim_valid_depth());
    // Over the pixels no person covers (the simulator's ground-truth mask; null without it).
    s["frames_with_dynamic_mask"] = q.frames_with_dynamic_mask();
    s["psnr_static_db"] = io::finite_or_null(q.mean_psnr_static_db());
    s["psnr_static_valid_depth_db"] = io::finite_or_null(q.mean_psnr_static_valid_depth_db());
    // Per frame, in time order: where along the run the map renders well or badly (a drift
    // seen on a revisit, an area trained less, people in view). Whole frame, and PSNR over
    // valid depth (null for a frame without a depth image), and over the static scene (null
    // for a frame without a person mask).
    io::Json t = io::Json::array(), psnr = io::Json::array(), ssim = io::Json::array(),
             psnr_valid = io::Json::array(), psnr_static = io::Json::array(),
             psnr_static_valid = io::Json::array();
    const auto value = [](double v, int digits) {
      return std::isfinite(v) ? io::fixed(v, digits) : io::Json(nullptr);
    };
    for (std::size_t i = 0; i < q.frames(); ++i) {
      t.push_back(io::fixed(q.t_s[i], 3));
      psnr.push_back(value(q.psnr_db[i], 3));
      ssim.push_back(value(q.ssim[i], 4));
      // one value per frame in every vector (QualitySet), NaN -> null
      psnr_valid.push_back(value(q.psnr_valid_depth_db[i], 3));
      psnr_static.push_back(value(q.psnr_static_db[i], 3));
      psnr_static_valid.push_back(value(q.psnr_static_valid_depth_db[i], 3));
    }
    s["per_frame"] = io::Json{{"t_s", std::move(t)},
                              {"psnr_db", std::move(psnr)},
                              {"ssim", std::move(ssim)},
                              {"psnr_valid_depth_db", std::move(psnr_valid)},
                              {"psnr_static_db", std::move(psnr_static)},
                              {"psnr_static_valid_depth_db", std::move(psnr_static_valid)}};
    return s;
  };
  j["plots"] = r.plots;
  if (r.quality_measured) {
    io::Json q;
    q["every_nth"] = set_json(r.quality.every_nth);
    q["held_out"] = r.have_keyframes ? set_json(r.quality.held_out) : io::Json(nullptr);
    q["rendered_views"] = r.quality.side_by_side_png;
    q["render_poses"] = r.rendered_at_ground_truth ? "ground_truth" : "estimate";
    j["quality"] = std::move(q);
  } else {
    j["quality"] = nullptr;
  }
  j["gaussians"] = r.gaussians >= 0 ? io::Json(r.gaussians) : io::Json(nullptr);
  j["input_damage"] = io::mcap::damage_object(r.input_damage, r.input_damage_used);
  j["fps"] = io::finite_or_null(r.run_stats.fps);
  j["peak_rss_bytes"] = io::finite_or_null(r.run_stats.peak_rss_bytes);
  j["lpips"] = nullptr;
  return io::json_line(j);
}

}  // namespace vigs::eval
