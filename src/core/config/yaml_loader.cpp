#include "core/config/yaml_loader.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include "core/config/diagnostics.hpp"

namespace vigs::config {
namespace {

std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string format_number(double v) {
  char buf[32];
  auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

/// Walks the schema and the YAML tree together. One Level per open mapping.
class YamlLoader final : public Visitor {
 public:
  YamlLoader(const YAML::Node& root, std::string file, std::vector<Diagnostic>& out)
      : file_(std::move(file)), out_(out) {
    const bool is_map = root.IsDefined() && root.IsMap();
    if (root.IsDefined() && !root.IsNull() && !is_map) {
      report(root.Mark(), "", "the top level must be a mapping of sections");
    }
    levels_.push_back({is_map ? root : YAML::Node(YAML::NodeType::Undefined), "", {}, {}});
  }

  void finish() { check_unknown(levels_.back()); }

  void field(std::string_view key, double& value, const FieldInfo& info) override {
    const auto node = lookup(key);
    if (!node) return;
    double parsed = 0.0;
    if (!parse_double(node, key, parsed)) return;
    if (check_range(node, key, parsed, info)) value = parsed;
  }

  void field(std::string_view key, int& value, const FieldInfo& info) override {
    const auto node = lookup(key);
    if (!node) return;
    if (!node.IsScalar()) return type_error(node, key, "an integer");
    const std::string& s = node.Scalar();
    long long parsed = 0;
    const auto res = std::from_chars(s.data(), s.data() + s.size(), parsed);
    if (res.ec != std::errc() || res.ptr != s.data() + s.size()) {
      return type_error(node, key, "an integer");
    }
    if (check_range(node, key, static_cast<double>(parsed), info)) value = static_cast<int>(parsed);
  }

  void field(std::string_view key, bool& value, std::string_view) override {
    const auto node = lookup(key);
    if (!node) return;
    if (!node.IsScalar()) return type_error(node, key, "true or false");
    const std::string& s = node.Scalar();
    if (s == "true") {
      value = true;
    } else if (s == "false") {
      value = false;
    } else {
      type_error(node, key, "true or false");
    }
  }

  void field(std::string_view key, std::string& value, Choices choices, std::string_view) override {
    const auto node = lookup(key);
    if (!node) return;
    if (!node.IsScalar()) return type_error(node, key, "a string");
    const std::string& s = node.Scalar();
    if (choices.size() > 0 && std::find(choices.begin(), choices.end(), s) == choices.end()) {
      std::string allowed;
      for (auto c : choices) allowed += (allowed.empty() ? "" : ", ") + std::string(c);
      return report(node.Mark(), path(key), "'" + s + "' is not one of: " + allowed);
    }
    value = s;
  }

  void field(std::string_view key, double* values, int count, const FieldInfo& info) override {
    const auto node = lookup(key);
    if (!node) return;
    const std::string expected = "a list of " + std::to_string(count) + " numbers";
    if (!node.IsSequence()) return type_error(node, key, expected);
    // A 3x3 matrix may also be written as three rows of three.
    std::vector<YAML::Node> flat;
    for (const auto& item : node) {
      if (item.IsSequence()) {
        for (const auto& inner : item) flat.push_back(inner);
      } else {
        flat.push_back(item);
      }
    }
    if (static_cast<int>(flat.size()) != count) {
      return report(node.Mark(), path(key),
                    "expected " + expected + ", got " + std::to_string(flat.size()));
    }
    std::vector<double> parsed(flat.size());
    bool ok = true;
    for (std::size_t i = 0; i < flat.size(); ++i) {
      ok =
          parse_double(flat[i], key, parsed[i]) && check_range(flat[i], key, parsed[i], info) && ok;
    }
    if (ok) std::copy(parsed.begin(), parsed.end(), values);
  }

  void require(bool ok, std::string_view key, std::string_view message) override {
    if (ok) return;
    const auto& level = levels_.back();
    const YAML::Node child = child_of(level.node, key);
    const YAML::Mark mark = child.IsDefined()        ? child.Mark()
                            : level.node.IsDefined() ? level.node.Mark()
                                                     : YAML::Mark::null_mark();
    report(mark, path(key), std::string(message));
  }

 protected:
  bool enter(std::string_view key) override {
    auto& parent = levels_.back();
    parent.known.insert(std::string(key));
    // yaml-cpp: a missing key yields an invalid node that must never be assigned to, so
    // nodes are only ever copy-constructed here.
    const YAML::Node child = child_of(parent.node, key);
    const bool is_section = child.IsDefined() && child.IsMap();
    if (child.IsDefined() && !child.IsNull() && !is_section) {
      report(child.Mark(), path(key), "expected a mapping (a section of keys)");
    }
    levels_.push_back(
        {is_section ? child : YAML::Node(YAML::NodeType::Undefined), path(key), {}, {}});
    return true;  // Visit even when absent so that cross-field rules still run on defaults.
  }

  void leave() override {
    check_unknown(levels_.back());
    levels_.pop_back();
  }

 private:
  struct Level {
    YAML::Node node;  // invalid/null when the section is absent
    std::string prefix;
    std::set<std::string> known;
    std::set<std::string> present;
  };

  [[nodiscard]] std::string path(std::string_view key) const {
    const auto& prefix = levels_.back().prefix;
    return prefix.empty() ? std::string(key) : prefix + "." + std::string(key);
  }

  static YAML::Node child_of(const YAML::Node& node, std::string_view key) {
    if (!node.IsDefined() || !node.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    YAML::Node child = node[std::string(key)];
    return child.IsDefined() ? child : YAML::Node(YAML::NodeType::Undefined);
  }

  YAML::Node lookup(std::string_view key) {
    auto& level = levels_.back();
    level.known.insert(std::string(key));
    YAML::Node child = child_of(level.node, key);
    if (!child.IsDefined()) return child;
    level.present.insert(std::string(key));
    if (child.IsNull()) {
      report(child.Mark(), path(key), "has no value; delete the key to use the default");
      return YAML::Node(YAML::NodeType::Undefined);
    }
    return child;
  }

  bool parse_double(const YAML::Node& node, std::string_view key, double& out) {
    if (!node.IsScalar()) {
      type_error(node, key, "a number");
      return false;
    }
    const std::string& s = node.Scalar();
    const char* begin = s.data();
    if (!s.empty() && s[0] == '+') ++begin;
    const auto res = std::from_chars(begin, s.data() + s.size(), out);
    if (res.ec != std::errc() || res.ptr != s.data() + s.size() || !std::isfinite(out)) {
      type_error(node, key, "a finite number");
      return false;
    }
    return true;
  }

  bool check_range(const YAML::Node& node, std::string_view key, double v, const FieldInfo& info) {
    if (v >= info.min && v <= info.max) return true;
    report(node.Mark(), path(key),
           "value " + format_number(v) + " is out of range [" + format_number(info.min) + ", " +
               format_number(info.max) + "] " + std::string(info.unit));
    return false;
  }

  void type_error(const YAML::Node& node, std::string_view key, const std::string& expected) {
    std::string got = node.IsScalar()     ? "'" + node.Scalar() + "'"
                      : node.IsSequence() ? std::string("a list")
                      : node.IsMap()      ? std::string("a mapping")
                                          : std::string("nothing");
    report(node.Mark(), path(key), "expected " + expected + ", got " + got);
  }

  void check_unknown(const Level& level) {
    if (!level.node.IsDefined() || !level.node.IsMap()) return;
    for (const auto& kv : level.node) {
      const std::string name = kv.first.as<std::string>("");
      if (level.known.count(name)) continue;
      std::string message = "unknown key";
      std::string best;
      std::size_t best_d = 3;  // suggest only close matches
      for (const auto& k : level.known) {
        const auto d = edit_distance(name, k);
        if (d < best_d) best_d = d, best = k;
      }
      if (!best.empty()) message += " (did you mean '" + best + "'?)";
      const std::string full = level.prefix.empty() ? name : level.prefix + "." + name;
      report(kv.first.Mark(), full, message);
    }
  }

  void report(const YAML::Mark& mark, const std::string& key, std::string message) {
    Diagnostic d;
    d.file = file_;
    if (!mark.is_null()) {
      d.line = mark.line + 1;
      d.column = mark.column + 1;
    }
    d.key = key;
    d.message = std::move(message);
    out_.push_back(std::move(d));
  }

  std::string file_;
  std::vector<Diagnostic>& out_;
  std::vector<Level> levels_;
};

}  // namespace

RobotConfig load_config_text(std::string_view yaml_text, const std::string& file_name) {
  if (yaml_text.size() > kMaxConfigBytes) {
    throw ConfigError({Diagnostic{file_name, 0, 0, "",
                                  "file is " + std::to_string(yaml_text.size()) +
                                      " bytes; a robot configuration is at most " +
                                      std::to_string(kMaxConfigBytes) + " bytes"}});
  }
  std::vector<Diagnostic> diagnostics;
  YAML::Node root;
  RobotConfig config;
  try {
    try {
      root = YAML::Load(std::string(yaml_text));
    } catch (const YAML::Exception& e) {
      Diagnostic d{file_name, e.mark.is_null() ? 0 : e.mark.line + 1,
                   e.mark.is_null() ? 0 : e.mark.column + 1, "", "YAML syntax error: " + e.msg};
      throw ConfigError({d});
    }
    YamlLoader loader(root, file_name, diagnostics);
    config.visit(loader);
    loader.finish();
  } catch (const std::bad_alloc&) {
    throw ConfigError({Diagnostic{file_name, 0, 0, "", "out of memory while parsing"}});
  }
  if (!diagnostics.empty()) {
    std::stable_sort(diagnostics.begin(), diagnostics.end(),
                     [](const Diagnostic& a, const Diagnostic& b) { return a.line < b.line; });
    throw ConfigError(std::move(diagnostics));
  }
  return config;
}

RobotConfig load_config_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError({Diagnostic{path, 0, 0, "", "cannot open file"}});
  // Read at most one byte past the limit, so a huge file is refused without being read whole.
  std::string text(kMaxConfigBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw ConfigError({Diagnostic{path, 0, 0, "", "read error"}});
  if (text.size() > kMaxConfigBytes) {
    throw ConfigError({Diagnostic{path, 0, 0, "",
                                  "file is larger than " + std::to_string(kMaxConfigBytes) +
                                      " bytes; a robot configuration is at most that"}});
  }
  return load_config_text(text, path);
}

}  // namespace vigs::config

namespace vigs::config {

Diagnostic diagnose_key(const std::string& path, const std::string& dotted_key,
                        std::string message) {
  Diagnostic d{path, 0, 0, dotted_key, std::move(message)};
  try {
    YAML::Node node = YAML::LoadFile(path);
    std::size_t start = 0;
    while (node.IsDefined() && node.IsMap()) {
      const std::size_t dot = dotted_key.find('.', start);
      const std::string part = dotted_key.substr(start, dot - start);
      const YAML::Node& parent = node;
      YAML::Node child = parent[part];
      if (!child.IsDefined()) break;
      if (dot == std::string::npos) {
        d.line = child.Mark().line + 1;
        d.column = child.Mark().column + 1;
        break;
      }
      node.reset(child);
      start = dot + 1;
    }
  } catch (const YAML::Exception&) {
    // The file loaded once already; without a location the diagnostic still names file and key.
  }
  return d;
}

}  // namespace vigs::config
