#include "pipeline/results_dir.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>

#include "io/json_text.hpp"

namespace vigs::pipeline {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ResultsFileError(path + ": cannot be opened");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Byte offset (0-based) of a nlohmann parse error: the start of the offending token, or the
/// text's end when the input ran out. nlohmann reports the 1-based position of the last byte
/// it read; stepping back over a bare word ("fast", "12.5e") names where the bad value starts.
std::size_t error_offset(const std::string& text, std::size_t last_read_1based, bool at_end) {
  if (at_end || last_read_1based == 0 || last_read_1based > text.size()) return text.size();
  std::size_t at = last_read_1based - 1;
  const auto word = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '+' || c == '-' || c == '.';
  };
  if (word(text[at])) {
    while (at > 0 && word(text[at - 1])) --at;
  }
  return at;
}

/// The file's one JSON object, parsed by nlohmann-json. Messages keep the form
/// "NAME: byte N: what" with the wording the RESULTS_DIR contract has always used.
io::Json parse_object(const std::string& text, const std::string& name) {
  const std::size_t first = text.find_first_not_of(" \t\n\r");
  if (first == std::string::npos || text[first] != '{') {
    throw ResultsFileError(name + ": byte " +
                           std::to_string(first == std::string::npos ? text.size() : first) +
                           ": expected '{'");
  }
  try {
    return io::Json::parse(text);
  } catch (const io::Json::parse_error& e) {
    const std::string msg = e.what();
    const bool at_end = msg.find("unexpected end of input") != std::string::npos;
    std::string what;
    if (msg.find("expected end of input") != std::string::npos && !at_end) {
      what = "trailing text after the object";
    } else if (at_end) {
      what = "unterminated object or array";
    } else if (msg.find("expected string literal") != std::string::npos) {
      what = "expected '\"'";
    } else {
      // nlohmann's own description, without its "[json.exception...] ..., column N: " prefix.
      const std::size_t colon = msg.find(": ", msg.find("column"));
      what = colon == std::string::npos ? msg : msg.substr(colon + 2);
    }
    throw ResultsFileError(name + ": byte " + std::to_string(error_offset(text, e.byte, at_end)) +
                           ": " + what);
  } catch (const io::Json::exception& e) {  // e.g. a number out of double range
    throw ResultsFileError(name + ": " + e.what());
  }
}

}  // namespace

RunStats parse_run_stats(const std::string& text, const std::string& name) {
  const io::Json doc = parse_object(text, name);
  RunStats st;
  const std::pair<const char*, std::optional<double>*> keys[] = {
      {"frames", &st.frames},
      {"wall_s", &st.wall_s},
      {"fps", &st.fps},
      {"peak_rss_bytes", &st.peak_rss_bytes},
      {"gaussians", &st.gaussians},
  };
  for (const auto& [key, slot] : keys) {
    const auto it = doc.find(key);
    if (it == doc.end() || it->is_null()) continue;
    if (!it->is_number()) {
      throw ResultsFileError(name + ": key \"" + key + "\" must be a number or null");
    }
    const double v = it->get<double>();
    if (v < 0) throw ResultsFileError(name + ": key \"" + key + "\" must not be negative");
    *slot = v;
  }
  if (const auto it = doc.find("map_poses"); it != doc.end() && !it->is_null()) {
    if (!it->is_string() || (*it != "estimate" && *it != "ground_truth"))
      throw ResultsFileError(name + ": key \"map_poses\" must be \"estimate\" or \"ground_truth\"");
    st.map_poses = it->get<std::string>();
  }
  return st;
}

RunStats read_run_stats(const std::string& path) {
  return parse_run_stats(read_text(path), path);
}

std::vector<double> read_keyframe_times(const std::string& path) {
  const std::string text = read_text(path);
  std::vector<double> out;
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    std::size_t a = line.find_first_not_of(" \t\r");
    if (a == std::string::npos || line[a] == '#') continue;
    std::size_t b = line.find_first_of(" \t\r,", a);
    if (b == std::string::npos) b = line.size();
    double t = 0;
    const auto r = std::from_chars(line.data() + a, line.data() + b, t);
    if (r.ec != std::errc() || r.ptr != line.data() + b || !std::isfinite(t))
      throw ResultsFileError(path + ":" + std::to_string(n) + ": '" + line.substr(a, b - a) +
                             "' is not a timestamp in seconds");
    out.push_back(t);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string format_keyframe_times(const std::vector<double>& t_s) {
  std::string out = "# keyframe timestamps, s\n";
  for (const double t : t_s) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, t);
    out.append(buf, r.ptr);
    out += '\n';
  }
  return out;
}

}  // namespace vigs::pipeline
