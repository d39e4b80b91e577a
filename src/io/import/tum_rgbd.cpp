#include "io/import/tum_rgbd.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <vector>

#include "core/types/image.hpp"
#include "io/image_io.hpp"
#include "io/recording/recording_writer.hpp"

namespace vigs::io {
namespace {

/// Whitespace-separated fields of the data lines of a TUM text file, with their line numbers.
struct Line {
  int number = 0;
  std::vector<std::string> fields;
};

std::vector<Line> read_lines(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ImportError(path + ": cannot open");
  std::vector<Line> lines;
  std::string text;
  int number = 0;
  while (std::getline(in, text)) {
    ++number;
    const auto first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#') continue;
    Line line{number, {}};
    std::istringstream fields(text);
    for (std::string f; fields >> f;) line.fields.push_back(f);
    lines.push_back(std::move(line));
  }
  if (in.bad()) throw ImportError(path + ": read error");
  return lines;
}

std::string where(const std::string& path, const Line& line) {
  return path + ":" + std::to_string(line.number);
}

double parse_double(const std::string& text, const std::string& at, const char* field) {
  double v = 0.0;
  const auto res = std::from_chars(text.data(), text.data() + text.size(), v);
  if (res.ec != std::errc() || res.ptr != text.data() + text.size() || !std::isfinite(v)) {
    throw ImportError(at + ": " + field + " '" + text + "' is not a finite number");
  }
  return v;
}

void check_fields(const std::string& path, const Line& line, std::size_t count,
                  const char* layout) {
  if (line.fields.size() != count) {
    throw ImportError(where(path, line) + ": expected " + std::to_string(count) + " fields (" +
                      layout + "), got " + std::to_string(line.fields.size()));
  }
}

void check_order(const std::string& path, const Line& line, std::int64_t prev_ns,
                 std::int64_t t_ns) {
  if (t_ns < prev_ns) throw ImportError(where(path, line) + ": timestamp goes backwards");
}

}  // namespace

std::int64_t parse_seconds_to_ns(const std::string& text, const std::string& at) {
  const auto dot = text.find('.');
  const std::string whole = text.substr(0, dot);
  std::string frac = dot == std::string::npos ? "" : text.substr(dot + 1);
  const auto digits = [](const std::string& s) {
    return std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (whole.empty() || !digits(whole) || !digits(frac) || frac.size() > 9 || whole.size() > 10) {
    throw ImportError(at + ": timestamp '" + text +
                      "' is not seconds as digits with at most 9 decimals");
  }
  frac.resize(9, '0');
  return std::stoll(whole) * 1'000'000'000LL + std::stoll(frac);
}

std::vector<StampedFile> read_tum_file_list(const std::string& path) {
  std::vector<StampedFile> out;
  for (const Line& line : read_lines(path)) {
    check_fields(path, line, 2, "timestamp filename");
    const std::int64_t t_ns = parse_seconds_to_ns(line.fields[0], where(path, line));
    check_order(path, line, out.empty() ? t_ns : out.back().t_ns, t_ns);
    out.push_back({t_ns, line.fields[1]});
  }
  return out;
}

std::vector<StampedPose> read_tum_groundtruth(const std::string& path) {
  std::vector<StampedPose> out;
  for (const Line& line : read_lines(path)) {
    check_fields(path, line, 8, "timestamp tx ty tz qx qy qz qw");
    const std::string at = where(path, line);
    const std::int64_t t_ns = parse_seconds_to_ns(line.fields[0], at);
    check_order(path, line, out.empty() ? t_ns : out.back().t_ns, t_ns);
    double v[7];
    static const char* kNames[7] = {"tx", "ty", "tz", "qx", "qy", "qz", "qw"};
    for (int i = 0; i < 7; ++i)
      v[i] = parse_double(line.fields[static_cast<std::size_t>(i + 1)], at, kNames[i]);
    Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
    if (q.norm() < 1e-6) throw ImportError(at + ": quaternion has zero norm");
    q.normalize();
    geometry::Pose T = geometry::Pose::Identity();
    T.linear() = q.toRotationMatrix();
    T.translation() = Eigen::Vector3d(v[0], v[1], v[2]);
    out.push_back({t_ns, T});
  }
  return out;
}

std::vector<StampedVector3> read_tum_accelerometer(const std::string& path) {
  std::vector<StampedVector3> out;
  for (const Line& line : read_lines(path)) {
    check_fields(path, line, 4, "timestamp ax ay az");
    const std::string at = where(path, line);
    StampedVector3 s;
    s.t_ns = parse_seconds_to_ns(line.fields[0], at);
    check_order(path, line, out.empty() ? s.t_ns : out.back().t_ns, s.t_ns);
    static const char* kNames[3] = {"ax", "ay", "az"};
    for (int i = 0; i < 3; ++i)
      s.xyz[i] = parse_double(line.fields[static_cast<std::size_t>(i + 1)], at, kNames[i]);
    out.push_back(s);
  }
  return out;
}

TumImportStats import_tum_rgbd(const TumImportOptions& o) {
  const auto file = [&o](const char* name) { return (o.dir / name).string(); };
  if (!(o.depth_units_per_m > 0.0) || !std::isfinite(o.depth_units_per_m)) {
    throw ImportError("depth units per metre must be positive and finite");
  }
  const auto rgb = read_tum_file_list(file("rgb.txt"));
  const auto depth = read_tum_file_list(file("depth.txt"));
  std::vector<StampedPose> gt;
  std::vector<StampedVector3> accel;
  if (std::filesystem::exists(o.dir / "groundtruth.txt"))
    gt = read_tum_groundtruth(file("groundtruth.txt"));
  if (std::filesystem::exists(o.dir / "accelerometer.txt")) {
    accel = read_tum_accelerometer(file("accelerometer.txt"));
  }

  // Colour-depth pairs: nearest depth within the gap, each depth used once.
  struct Pair {
    std::size_t rgb, depth;
  };
  std::vector<Pair> pairs;
  std::vector<char> used(depth.size(), 0);
  TumImportStats stats;
  for (std::size_t i = 0; i < rgb.size(); ++i) {
    const auto it =
        std::lower_bound(depth.begin(), depth.end(), rgb[i].t_ns,
                         [](const StampedFile& d, std::int64_t t) { return d.t_ns < t; });
    std::size_t best = depth.size();
    std::int64_t best_gap = o.max_pair_gap_ns + 1;
    for (auto c : {it - depth.begin() - 1, it - depth.begin()}) {
      if (c < 0 || static_cast<std::size_t>(c) >= depth.size() || used[static_cast<std::size_t>(c)])
        continue;
      const std::int64_t gap = std::abs(depth[static_cast<std::size_t>(c)].t_ns - rgb[i].t_ns);
      if (gap < best_gap) best = static_cast<std::size_t>(c), best_gap = gap;
    }
    if (best == depth.size()) {
      ++stats.colour_without_depth;
      continue;
    }
    used[best] = 1;
    stats.max_pair_gap_ns = std::max(stats.max_pair_gap_ns, best_gap);
    pairs.push_back({i, best});
  }
  if (pairs.empty())
    throw ImportError(file("rgb.txt") +
                      ": no colour image has a depth image within the pairing gap");

  RecordingWriterOptions wo;
  wo.depth_encoding = "32FC1";
  RecordingWriter writer(o.out, wo);
  // The recording is written in time order: IMU and ground truth up to each frame, then it.
  std::size_t next_gt = 0, next_accel = 0;
  const auto flush_until = [&](std::int64_t t_ns) {
    while (true) {
      const bool has_a = next_accel < accel.size() && accel[next_accel].t_ns <= t_ns;
      const bool has_g = next_gt < gt.size() && gt[next_gt].t_ns <= t_ns;
      if (!has_a && !has_g) break;
      if (has_a && (!has_g || accel[next_accel].t_ns <= gt[next_gt].t_ns)) {
        ImuSample s;
        s.t_ns = accel[next_accel].t_ns;
        for (int k = 0; k < 3; ++k) s.accel_mps2[k] = accel[next_accel].xyz[k];
        writer.imu(s, -1.0, o.accel_variance_mps4);
        ++next_accel;
        ++stats.accelerometer;
      } else {
        writer.ground_truth(gt[next_gt].t_ns, gt[next_gt].T_w_c);
        ++next_gt;
        ++stats.ground_truth;
      }
    }
  };

  PinholeCamera camera = o.camera;
  std::vector<float> depth_m;
  for (const Pair& p : pairs) {
    const std::string rgb_path = (o.dir / rgb[p.rgb].path).string();
    const std::string depth_path = (o.dir / depth[p.depth].path).string();
    const ImageU8 color = read_rgb(rgb_path);
    const ImageU16 raw = read_png_u16(depth_path);
    if (camera.width_px == 0 && camera.height_px == 0) {
      camera.width_px = color.width;
      camera.height_px = color.height;
    }
    if (color.width != camera.width_px || color.height != camera.height_px) {
      throw ImportError(rgb_path + ": " + std::to_string(color.width) + "x" +
                        std::to_string(color.height) + " differs from the camera's " +
                        std::to_string(camera.width_px) + "x" + std::to_string(camera.height_px));
    }
    if (raw.width != color.width || raw.height != color.height) {
      throw ImportError(depth_path + ": " + std::to_string(raw.width) + "x" +
                        std::to_string(raw.height) + " differs from its colour image " + rgb_path);
    }
    depth_m.resize(raw.data.size());
    for (std::size_t k = 0; k < raw.data.size(); ++k) {
      depth_m[k] = static_cast<float>(raw.data[k] / o.depth_units_per_m);
    }
    const std::int64_t t_ns = rgb[p.rgb].t_ns;
    flush_until(t_ns);
    writer.frame(t_ns, camera, color.data, false, depth_m);
    ++stats.frames;
  }
  flush_until(std::numeric_limits<std::int64_t>::max());
  writer.close();
  return stats;
}

}  // namespace vigs::io
