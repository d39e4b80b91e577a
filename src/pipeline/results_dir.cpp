#include "pipeline/results_dir.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace vigs::pipeline {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ResultsFileError(path + ": cannot be opened");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// A small JSON reader: the top-level object's members, numbers kept, anything else skipped.
class JsonScanner {
 public:
  JsonScanner(const std::string& text, const std::string& name) : s_(text), name_(name) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw ResultsFileError(name_ + ": byte " + std::to_string(i_) + ": " + what);
  }
  void ws() {
    while (i_ < s_.size() && (s_[i_] == ' ' || s_[i_] == '\t' || s_[i_] == '\n' || s_[i_] == '\r'))
      ++i_;
  }
  bool peek(char c) {
    ws();
    return i_ < s_.size() && s_[i_] == c;
  }
  void expect(char c) {
    if (!peek(c)) fail(std::string("expected '") + c + "'");
    ++i_;
  }
  std::string string() {
    expect('"');
    std::string out;
    while (i_ < s_.size() && s_[i_] != '"') {
      if (s_[i_] == '\\') {
        if (++i_ >= s_.size()) break;
        if (s_[i_] == 'u') i_ += 4;  // key names we look for are plain ASCII
      }
      out += s_[i_++];
    }
    if (i_ >= s_.size()) fail("unterminated string");
    ++i_;
    return out;
  }
  /// A value: returns the number, nullopt for null; other kinds are skipped (kind set).
  std::optional<double> value(bool& is_number, bool& is_null) {
    ws();
    is_number = is_null = false;
    if (i_ >= s_.size()) fail("value expected");
    const char c = s_[i_];
    if (c == '"') {
      string();
    } else if (c == '{' || c == '[') {
      skip_nested();
    } else if (s_.compare(i_, 4, "null") == 0) {
      i_ += 4;
      is_null = true;
    } else if (s_.compare(i_, 4, "true") == 0) {
      i_ += 4;
    } else if (s_.compare(i_, 5, "false") == 0) {
      i_ += 5;
    } else {
      double v = 0;
      const auto r = std::from_chars(s_.data() + i_, s_.data() + s_.size(), v);
      if (r.ec != std::errc() || !std::isfinite(v)) fail("not a JSON value");
      i_ = static_cast<std::size_t>(r.ptr - s_.data());
      is_number = true;
      return v;
    }
    return std::nullopt;
  }
  bool at_end() {
    ws();
    return i_ >= s_.size();
  }

 private:
  void skip_nested() {
    int depth = 0;
    do {
      if (i_ >= s_.size()) fail("unterminated object or array");
      const char c = s_[i_];
      if (c == '"') {
        string();
        continue;
      }
      if (c == '{' || c == '[') ++depth;
      if (c == '}' || c == ']') --depth;
      ++i_;
    } while (depth > 0);
  }
  const std::string& s_;
  const std::string& name_;
  std::size_t i_ = 0;
};

}  // namespace

RunStats parse_run_stats(const std::string& text, const std::string& name) {
  JsonScanner js(text, name);
  RunStats st;
  js.expect('{');
  if (js.peek('}')) {
    js.expect('}');
  } else {
    for (;;) {
      const std::string key = js.string();
      js.expect(':');
      bool is_number = false, is_null = false;
      const std::optional<double> v = js.value(is_number, is_null);
      std::optional<double>* slot = nullptr;
      if (key == "frames") slot = &st.frames;
      if (key == "wall_s") slot = &st.wall_s;
      if (key == "fps") slot = &st.fps;
      if (key == "peak_rss_bytes") slot = &st.peak_rss_bytes;
      if (key == "gaussians") slot = &st.gaussians;
      if (slot != nullptr) {
        if (!is_number && !is_null)
          throw ResultsFileError(name + ": key \"" + key + "\" must be a number or null");
        if (is_number && *v < 0)
          throw ResultsFileError(name + ": key \"" + key + "\" must not be negative");
        *slot = v;
      }
      if (js.peek(',')) {
        js.expect(',');
        continue;
      }
      js.expect('}');
      break;
    }
  }
  if (!js.at_end()) js.fail("trailing text after the object");
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
