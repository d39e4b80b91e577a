#include "io/tum_trajectory.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "io/atomic_file.hpp"
#include "io/io_error.hpp"

namespace vigs::io {
namespace {

bool is_separator(char c) {
  return c == ' ' || c == '\t' || c == ',' || c == '\r';
}

}  // namespace

std::vector<TumPose> parse_tum_trajectory(std::string_view text, const std::string& name) {
  std::vector<TumPose> poses;
  std::size_t line_no = 0;
  while (!text.empty()) {
    const std::size_t eol = text.find('\n');
    std::string_view line = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view{} : text.substr(eol + 1);
    ++line_no;
    std::size_t i = 0;
    while (i < line.size() && is_separator(line[i])) ++i;
    if (i == line.size() || line[i] == '#') continue;
    double v[8];
    int count = 0;
    while (i < line.size()) {
      if (count == 8) {
        throw IoError(name + ":" + std::to_string(line_no) +
                      ": more than 8 fields (expected 't tx ty tz qx qy qz qw')");
      }
      if (line[i] == '+') ++i;  // from_chars takes no leading '+'
      const char* begin = line.data() + i;
      const auto [end, ec] = std::from_chars(begin, line.data() + line.size(), v[count]);
      if (ec != std::errc{} || !std::isfinite(v[count]) ||
          (end != line.data() + line.size() && !is_separator(*end))) {
        std::size_t j = i;
        while (j < line.size() && !is_separator(line[j])) ++j;
        throw IoError(name + ":" + std::to_string(line_no) + ": field " +
                      std::to_string(count + 1) + " '" + std::string(line.substr(i, j - i)) +
                      "' is not a finite number");
      }
      ++count;
      i = static_cast<std::size_t>(end - line.data());
      while (i < line.size() && is_separator(line[i])) ++i;
    }
    if (count != 8) {
      throw IoError(name + ":" + std::to_string(line_no) + ": " + std::to_string(count) +
                    " fields, expected 8 ('t tx ty tz qx qy qz qw')");
    }
    TumPose p;
    p.t_s = v[0];
    p.p_w_m = Eigen::Vector3d(v[1], v[2], v[3]);
    p.q_w = Eigen::Quaterniond(v[7], v[4], v[5], v[6]);  // Eigen takes w first
    poses.push_back(p);
  }
  return poses;
}

std::vector<TumPose> read_tum_trajectory(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot open TUM trajectory " + path);
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw IoError("cannot read TUM trajectory " + path);
  return parse_tum_trajectory(ss.str(), path);
}

std::string format_tum_trajectory(std::span<const TumPose> poses) {
  std::string out;
  out.reserve(poses.size() * 120);
  char buf[32];
  auto put = [&](double x, char sep) {
    const auto r = std::to_chars(buf, buf + sizeof(buf), x);
    out.append(buf, r.ptr);
    out.push_back(sep);
  };
  for (const TumPose& p : poses) {
    put(p.t_s, ' ');
    put(p.p_w_m.x(), ' ');
    put(p.p_w_m.y(), ' ');
    put(p.p_w_m.z(), ' ');
    put(p.q_w.x(), ' ');
    put(p.q_w.y(), ' ');
    put(p.q_w.z(), ' ');
    put(p.q_w.w(), '\n');
  }
  return out;
}

void write_tum_trajectory(const std::string& path, std::span<const TumPose> poses) {
  const std::string text = format_tum_trajectory(poses);
  try {
    write_file_atomically(path, [&](std::FILE* f) {
      if (std::fwrite(text.data(), 1, text.size(), f) != text.size()) {
        throw IoError("short write to " + path);
      }
    });
  } catch (const IoError&) {
    throw;
  } catch (const std::exception& e) {
    throw IoError(std::string("cannot write TUM trajectory: ") + e.what());
  }
}

}  // namespace vigs::io
