#include "eval/render_quality.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "io/image_io.hpp"
#include "io/recording/recorded_frames.hpp"
#include "mapping/image_metrics.hpp"
#include "mapping/rasterizer.hpp"
#include "mapping/ssim.hpp"

namespace vigs::eval {
namespace {

/// Mean of the measured (non-NaN) values, NaN when there are none.
double mean_of(const std::vector<double>& v) {
  double sum = 0;
  std::size_t n = 0;
  for (const double x : v) {
    if (std::isnan(x)) continue;
    sum += x;
    ++n;
  }
  return n == 0 ? std::numeric_limits<double>::quiet_NaN() : sum / static_cast<double>(n);
}

std::size_t measured(const std::vector<double>& v) {
  return static_cast<std::size_t>(
      std::count_if(v.begin(), v.end(), [](double x) { return !std::isnan(x); }));
}

/// Index of the pose nearest to t within max_dt, or -1.
long nearest_pose(const Trajectory& tr, double t, double max_dt) {
  const auto it = std::lower_bound(tr.poses.begin(), tr.poses.end(), t,
                                   [](const TimedPose& p, double x) { return p.t_s < x; });
  long best = -1;
  double best_dt = max_dt;
  for (auto c : {it, it == tr.poses.begin() ? it : it - 1}) {
    if (c == tr.poses.end()) continue;
    const double dt = std::abs(c->t_s - t);
    if (dt <= best_dt) {
      best_dt = dt;
      best = static_cast<long>(c - tr.poses.begin());
    }
  }
  return best;
}

bool near_any(const std::vector<double>& sorted, double t, double tol) {
  const auto it = std::lower_bound(sorted.begin(), sorted.end(), t - tol);
  return it != sorted.end() && *it <= t + tol;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

/// PSNR (peak 255) over the pixels whose mask is set.
double masked_psnr(const ImageU8& a, const ImageU8& b, const std::vector<double>& mask) {
  double se = 0;
  std::size_t n = 0;
  for (std::size_t p = 0; p < mask.size(); ++p) {
    if (mask[p] == 0) continue;
    for (int c = 0; c < 3; ++c) {
      const double d = static_cast<double>(a.data[3 * p + c]) - b.data[3 * p + c];
      se += d * d;
    }
    n += 3;
  }
  if (n == 0) return std::numeric_limits<double>::quiet_NaN();
  if (se == 0) return std::numeric_limits<double>::infinity();
  return 10.0 * std::log10(255.0 * 255.0 * static_cast<double>(n) / se);
}

struct StaticPsnr {
  double whole_db = std::numeric_limits<double>::quiet_NaN();
  double valid_depth_db = std::numeric_limits<double>::quiet_NaN();
};

/// PSNR over the pixels no person covers (`person` 255 = a person, ground truth), and over
/// those that also have valid depth (`depth_m` null: the frame has none). `mask` is scratch.
StaticPsnr static_psnr(const ImageU8& recorded, const ImageU8& rendered, const std::uint8_t* person,
                       const ImageF32* depth_m, std::vector<double>& mask) {
  StaticPsnr out;
  const std::size_t n = static_cast<std::size_t>(recorded.width) * recorded.height;
  mask.resize(n);
  for (std::size_t p = 0; p < n; ++p) mask[p] = person[p] == 0 ? 1.0 : 0.0;
  out.whole_db = masked_psnr(recorded, rendered, mask);
  if (depth_m == nullptr) return out;
  for (std::size_t p = 0; p < n; ++p)
    if (!(depth_m->data[p] > 0)) mask[p] = 0.0;
  out.valid_depth_db = masked_psnr(recorded, rendered, mask);
  return out;
}

}  // namespace

std::size_t QualitySet::frames_with_depth() const {
  return measured(psnr_valid_depth_db);
}
std::size_t QualitySet::frames_with_dynamic_mask() const {
  return measured(psnr_static_db);
}
double QualitySet::mean_psnr_static_db() const {
  return mean_of(psnr_static_db);
}
double QualitySet::mean_psnr_static_valid_depth_db() const {
  return mean_of(psnr_static_valid_depth_db);
}
double QualitySet::mean_psnr_db() const {
  return mean_of(psnr_db);
}
double QualitySet::mean_ssim() const {
  return mean_of(ssim);
}
double QualitySet::mean_psnr_valid_depth_db() const {
  return mean_of(psnr_valid_depth_db);
}
double QualitySet::mean_ssim_valid_depth() const {
  return mean_of(ssim_valid_depth);
}
double QualitySet::min_psnr_db() const {
  return psnr_db.empty() ? std::numeric_limits<double>::quiet_NaN()
                         : *std::min_element(psnr_db.begin(), psnr_db.end());
}

RenderQuality measure_render_quality(const mapping::GaussianMap& map, const Trajectory& T_w_c,
                                     const std::vector<double>* keyframe_t_s,
                                     const std::string& mcap_path,
                                     const RenderQualityOptions& opt) {
  if (opt.every < 1) throw std::invalid_argument("render quality: every must be >= 1");
  if (opt.threads < 1) throw std::invalid_argument("render quality: threads must be >= 1");
  RenderQuality q;
  vigs::rt::WorkerTeam pool(opt.threads, vigs::rt::ThreadSpec{.name = "mapper_w1"});
  mapping::Rasterizer<float> ras(mapping::RasterSettings{}, &pool);
  mapping::RenderResult<float> r;
  ImageU8 rendered;
  // Side-by-side rows: the first every-n-th frame at or after evenly spaced times of the
  // estimate's span.
  std::vector<double> targets;
  if (!T_w_c.poses.empty() && opt.side_by_side_rows > 0 && !opt.side_by_side_png.empty()) {
    const double t0 = T_w_c.poses.front().t_s, t1 = T_w_c.poses.back().t_s;
    for (int k = 0; k < opt.side_by_side_rows; ++k)
      targets.push_back(t0 + (t1 - t0) * (k + 0.5) / opt.side_by_side_rows);
  }
  std::size_t next_target = 0;
  ImageU8 sbs;
  std::uint64_t held_out_seen = 0;
  mapping::SsimOptions so;  // the convention of mapping::image_quality with kGaussian11
  so.data_range = 255.0;
  mapping::Ssim<double> masked_ssim(so);
  std::vector<double> ref, test, mask, static_mask;
  ImageU8 f_rgb;       // the frame's colour as RGB
  ImageF32 f_depth_m;  // and depth, 0 = no measurement
  const auto on_frame = [&](const io::RecordedFrame& rec) {
    const double t_s = static_cast<double>(rec.view.t_ns) * 1e-9;  // header stamp
    const bool keyframe = keyframe_t_s && near_any(*keyframe_t_s, t_s, opt.keyframe_tol_s);
    if (keyframe) ++q.keyframe_frames;
    const bool in_nth = rec.index % static_cast<std::uint64_t>(opt.every) == 0;
    bool in_held_out = false;
    if (!keyframe && keyframe_t_s) {
      in_held_out = held_out_seen % static_cast<std::uint64_t>(opt.every) == 0;
      ++held_out_seen;
    }
    if (!in_nth && !in_held_out) return;
    const long pi = nearest_pose(T_w_c, t_s, opt.max_dt_s);
    if (pi < 0) {
      ++q.frames_without_pose;
      return;
    }
    copy_rgb8(rec.view, f_rgb);
    const bool has_depth = rec.view.has_depth();
    if (has_depth) copy_depth_m(rec.view, f_depth_m);
    const auto& T = T_w_c.poses[static_cast<std::size_t>(pi)].T_w_x;
    ras.forward(map, mapping::RenderCamera::from(rec.camera, T), r);
    rendered = ImageU8(f_rgb.width, f_rgb.height, 3);
    for (std::size_t i = 0; i < rendered.data.size(); ++i)
      rendered.data[i] =
          static_cast<std::uint8_t>(std::lround(255.0f * std::clamp(r.color[i], 0.0f, 1.0f)));
    const auto iq = mapping::image_quality(f_rgb, rendered, mapping::SsimWindow::kGaussian11);
    double psnr_v = std::numeric_limits<double>::quiet_NaN(), ssim_v = psnr_v;
    if (has_depth) {
      mask.resize(f_depth_m.data.size());
      bool any = false;
      for (std::size_t p = 0; p < mask.size(); ++p) {
        mask[p] = f_depth_m.data[p] > 0 ? 1.0 : 0.0;
        any = any || mask[p] != 0;
      }
      if (any) {
        ref.assign(f_rgb.data.begin(), f_rgb.data.end());
        test.assign(rendered.data.begin(), rendered.data.end());
        psnr_v = masked_psnr(f_rgb, rendered, mask);
        ssim_v = masked_ssim.evaluate(test.data(), ref.data(), f_rgb.width, f_rgb.height, 3,
                                      mask.data(), nullptr);
      }
    }
    StaticPsnr psnr_s;  // NaN without a person mask
    if (rec.dynamic_mask != nullptr)
      psnr_s = static_psnr(f_rgb, rendered, rec.dynamic_mask, has_depth ? &f_depth_m : nullptr,
                           static_mask);
    q.image_width = f_rgb.width;
    q.image_height = f_rgb.height;
    for (auto [set, on] : {std::pair{&q.every_nth, in_nth}, std::pair{&q.held_out, in_held_out}}) {
      if (!on) continue;
      set->t_s.push_back(t_s);
      set->psnr_db.push_back(iq.psnr_db);
      set->ssim.push_back(iq.ssim);
      set->psnr_valid_depth_db.push_back(psnr_v);
      set->ssim_valid_depth.push_back(ssim_v);
      set->psnr_static_db.push_back(psnr_s.whole_db);
      set->psnr_static_valid_depth_db.push_back(psnr_s.valid_depth_db);
    }
    if (in_nth && next_target < targets.size() && t_s >= targets[next_target]) {
      while (next_target < targets.size() && t_s >= targets[next_target]) ++next_target;
      const int w = f_rgb.width, h = f_rgb.height;
      const int row = static_cast<int>(q.side_by_side_t_s.size());
      if (sbs.empty()) sbs = ImageU8(2 * w, h * opt.side_by_side_rows, 3);
      if (sbs.width != 2 * w || sbs.height != h * opt.side_by_side_rows) return;  // size changed
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          for (int c = 0; c < 3; ++c) {
            sbs.at(x, row * h + y, c) = rendered.at(x, y, c);
            sbs.at(w + x, row * h + y, c) = f_rgb.at(x, y, c);
          }
      q.side_by_side_t_s.push_back(t_s);
    }
  };
  // With the person mask: the pixels no person covers are measured too.
  const auto stats = io::for_each_recorded_frame(
      mcap_path, on_frame, std::string(io::topics::kRgb.name),
      std::string(io::topics::kCameraInfo.name), std::string(io::topics::kDepth.name),
      io::kDepthPairToleranceNs, std::string(io::topics::kDynamicMask.name));
  q.damage = stats.damage;
  q.recorded_frames = stats.frames + stats.without_camera_info;
  q.frames_without_camera_info = stats.without_camera_info;
  if (!q.side_by_side_t_s.empty()) {
    // Rows never filled (short estimate) are cut off.
    sbs.height = sbs.height / opt.side_by_side_rows * static_cast<int>(q.side_by_side_t_s.size());
    sbs.data.resize(static_cast<std::size_t>(sbs.width) * sbs.height * 3);
    io::write_png(opt.side_by_side_png, sbs);
    q.side_by_side_png = opt.side_by_side_png;
    q.side_by_side_width = sbs.width;
    q.side_by_side_height = sbs.height;
  }
  return q;
}

std::string render_quality_markdown(const RenderQuality& q, const RenderQualityOptions& opt,
                                    bool have_keyframes, const std::string& png_relative,
                                    bool at_ground_truth) {
  std::string md = "## Rendering quality (PSNR, SSIM)\n\n";
  md += std::string("The map is rendered at the ") +
        (at_ground_truth ? "ground-truth camera pose (the run built the map at the ground "
                           "truth's poses, stats.json map_poses: the mapper alone, without "
                           "tracking error)"
                         : "estimated camera pose") +
        " of recorded frames (" + std::to_string(q.image_width) + "x" +
        std::to_string(q.image_height) +
        " px) and compared with the recorded colour image: PSNR with peak 255 over all pixels "
        "and channels, SSIM with the Gaussian 11x11 window (sigma 1.5) over valid windows, mean "
        "over channels. Means are per-frame means. " +
        std::to_string(q.recorded_frames) + " colour frames recorded, " +
        std::to_string(q.keyframe_frames) + " of them keyframes.\n\n";
  md +=
      "| set | frames | mean PSNR [dB] | min PSNR [dB] | mean SSIM | frames with depth | mean "
      "PSNR, valid depth [dB] | mean SSIM, valid depth | frames with person mask | mean PSNR, "
      "static [dB] | mean PSNR, static, valid depth [dB] |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n";
  // "-" where nothing was measured (no frame with depth or mask, or an exact match: inf dB).
  const auto db = [](double v) { return std::isfinite(v) ? fmt("%.2f", v) : std::string("-"); };
  const auto row = [&](const std::string& name, const QualitySet& s) {
    if (s.frames() == 0) return "| " + name + " | 0 | - | - | - | 0 | - | - | 0 | - | - |\n";
    const std::size_t nd = s.frames_with_depth();
    return "| " + name + " | " + std::to_string(s.frames()) + " | " +
           fmt("%.2f", s.mean_psnr_db()) + " | " + fmt("%.2f", s.min_psnr_db()) + " | " +
           fmt("%.4f", s.mean_ssim()) + " | " + std::to_string(nd) + " | " +
           (nd ? fmt("%.2f", s.mean_psnr_valid_depth_db()) : std::string("-")) + " | " +
           (nd ? fmt("%.4f", s.mean_ssim_valid_depth()) : std::string("-")) + " | " +
           std::to_string(s.frames_with_dynamic_mask()) + " | " + db(s.mean_psnr_static_db()) +
           " | " + db(s.mean_psnr_static_valid_depth_db()) + " |\n";
  };
  md += row("every " + std::to_string(opt.every) + "th frame", q.every_nth);
  if (have_keyframes) md += row("held-out (never keyframes)", q.held_out);
  md += "\n";
  if (!have_keyframes)
    md += "- Held-out frames: not measured, the run wrote no keyframes.txt.\n";
  else
    md += "- Held-out frames: farther than " + fmt("%.3g", opt.keyframe_tol_s) +
          " s from every keyframe stamp; every " + std::to_string(opt.every) +
          "th of them is used.\n";
  md +=
      "- Static: the pixels no walking person covers, from the recording's ground-truth "
      "person mask (`" +
      std::string(io::topics::kDynamicMask.name) +
      "`, written by the simulator): the map leaves people out by design, so this is its "
      "quality on the static scene; without the mask, not measured.\n";
  if (q.frames_without_pose > 0)
    md += "- " + std::to_string(q.frames_without_pose) +
          " selected frames had no estimated pose within " + fmt("%.3g", opt.max_dt_s) +
          " s and were skipped.\n";
  if (q.frames_without_camera_info > 0)
    md += "- " + std::to_string(q.frames_without_camera_info) +
          " colour frames came before any CameraInfo and were skipped.\n";
  md += "\n### Rendered views beside the recording\n\n";
  if (q.side_by_side_png.empty()) {
    md += "No rendered views were written (no frame with an estimated pose).\n\n";
  } else {
    md += "Left: rendered from the map at the estimated pose; right: recorded. Rows at t =";
    for (const double t : q.side_by_side_t_s) md += " " + fmt("%.3f", t) + " s";
    md += ".\n\n![rendered vs recorded](" + png_relative + ")\n\n";
  }
  return md;
}

}  // namespace vigs::eval
