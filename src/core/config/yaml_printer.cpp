#include "core/config/yaml_printer.hpp"

#include <charconv>
#include <sstream>

namespace vigs::config {
namespace {

std::string number(double v) {
  char buf[32];
  auto res = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, res.ptr);
  // Keep floats recognisable as such to a reader ("1" would read back fine, but "1.0" says more).
  if (s.find_first_of(".en") == std::string::npos) s += ".0";
  return s;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

class YamlPrinter final : public Visitor {
 public:
  std::string text() const { return out_.str(); }

  void field(std::string_view key, double& value, const FieldInfo& info) override {
    line(key, number(value), info);
  }
  void field(std::string_view key, int& value, const FieldInfo& info) override {
    line(key, std::to_string(value), info);
  }
  void field(std::string_view key, bool& value, std::string_view doc) override {
    line(key, value ? "true" : "false", "# " + std::string(doc));
  }
  void field(std::string_view key, std::string& value, Choices choices,
             std::string_view doc) override {
    std::string comment = "# ";
    if (choices.size() > 0) {
      comment += "one of";
      for (auto c : choices) comment += " " + std::string(c);
      comment += "; ";
    }
    line(key, quoted(value), comment + std::string(doc));
  }
  void field(std::string_view key, double* values, int count, const FieldInfo& info) override {
    std::string list = "[";
    for (int i = 0; i < count; ++i) list += (i ? ", " : "") + number(values[i]);
    line(key, list + "]", info);
  }
  void require(bool, std::string_view, std::string_view) override {}

 protected:
  bool enter(std::string_view key) override {
    out_ << indent() << key << ":\n";
    ++depth_;
    return true;
  }
  void leave() override { --depth_; }

 private:
  [[nodiscard]] std::string indent() const { return std::string(2 * depth_, ' '); }

  void line(std::string_view key, const std::string& value, const FieldInfo& info) {
    std::ostringstream comment;
    comment << "# [" << info.unit << "] range " << number(info.min) << " .. " << number(info.max)
            << "; " << info.doc;
    line(key, value, comment.str());
  }
  void line(std::string_view key, const std::string& value, const std::string& comment) {
    std::string head = indent() + std::string(key) + ": " + value;
    if (head.size() < 44) head.resize(44, ' ');
    out_ << head << "  " << comment << "\n";
  }

  std::ostringstream out_;
  int depth_ = 0;
};

}  // namespace

std::string print_config(RobotConfig config) {
  YamlPrinter printer;
  config.visit(printer);
  return printer.text();
}

}  // namespace vigs::config
