#include "pipeline/progress_line.hpp"

#include <cmath>
#include <cstdio>

namespace vigs::pipeline {

std::optional<double> progress_eta_s(std::uint64_t frames_played, std::uint64_t frames_total,
                                     double elapsed_s) {
  if (frames_total == 0) return std::nullopt;  // live: no end
  if (frames_played >= frames_total) return 0.0;
  if (frames_played == 0 || !(elapsed_s > 0.0) || !std::isfinite(elapsed_s)) return std::nullopt;
  const double frames_per_s = static_cast<double>(frames_played) / elapsed_s;
  return static_cast<double>(frames_total - frames_played) / frames_per_s;
}

std::string format_duration_hms(double t_s) {
  const long long total_s =
      std::isfinite(t_s) && t_s > 0.0 ? static_cast<long long>(std::llround(t_s)) : 0;
  const long long h = total_s / 3600, m = (total_s / 60) % 60, s = total_s % 60;
  char text[48];
  if (h > 0)
    std::snprintf(text, sizeof text, "%lld:%02lld:%02lld", h, m, s);
  else
    std::snprintf(text, sizeof text, "%lld:%02lld", m, s);
  return text;
}

std::string format_progress_line(const LiveProgress& p) {
  const double rtf = p.elapsed_s > 0 ? p.stream_s / p.elapsed_s : 0;
  char frames[48];
  if (p.frames_total > 0)
    std::snprintf(frames, sizeof frames, "%5llu/%llu", static_cast<unsigned long long>(p.frames),
                  static_cast<unsigned long long>(p.frames_total));
  else
    std::snprintf(frames, sizeof frames, "%5llu", static_cast<unsigned long long>(p.frames));
  std::string eta = "live";
  if (p.frames_total > 0) {
    const std::optional<double> eta_s =
        progress_eta_s(p.frames_played, p.frames_total, p.elapsed_s);
    eta = eta_s ? "ETA " + format_duration_hms(*eta_s) : "ETA --:--";
  }
  char line[256];
  std::snprintf(line, sizeof line,
                "frames %s  rtf %.2f  tracker p50 %.1f / p99 %.1f ms  drops %llu  gaussians %zu  ",
                frames, rtf, static_cast<double>(p.track_p50_ns) * 1e-6,
                static_cast<double>(p.track_p99_ns) * 1e-6,
                static_cast<unsigned long long>(p.drops), p.gaussians);
  return line + eta;
}

}  // namespace vigs::pipeline
