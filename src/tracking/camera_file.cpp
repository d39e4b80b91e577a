#include "tracking/camera_file.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

namespace vigs::tracking {

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw CameraFileError(name + ": " + what);
}

double number(const YAML::Node& node, const std::string& key, const std::string& name) {
  try {
    const double v = node.as<double>();
    if (!std::isfinite(v)) fail(name, "key '" + key + "' is not a finite number");
    return v;
  } catch (const YAML::Exception&) {
    fail(name,
         "key '" + key + "' is not a number (line " + std::to_string(node.Mark().line + 1) + ")");
  }
}

std::vector<double> numbers(const YAML::Node& root, const std::string& key, std::size_t count,
                            const std::string& name) {
  const YAML::Node node = root[key];
  if (!node.IsSequence() || node.size() != count) {
    fail(name, "key '" + key + "' must be a list of " + std::to_string(count) + " numbers");
  }
  std::vector<double> out;
  for (std::size_t i = 0; i < count; ++i) {
    out.push_back(number(node[i], key + "[" + std::to_string(i) + "]", name));
  }
  return out;
}

double required(const YAML::Node& root, const std::string& key, const std::string& name) {
  const YAML::Node node = root[key];
  if (!node) fail(name, "missing key '" + key + "'");
  return number(node, key, name);
}

void check(const PinholeCamera& c, const std::string& name) {
  if (c.width_px <= 0 || c.height_px <= 0) fail(name, "width and height must be positive");
  if (!(c.fx_px > 0.0) || !(c.fy_px > 0.0)) fail(name, "fx and fy must be positive");
  if (c.cx_px < 0.0 || c.cx_px >= c.width_px || c.cy_px < 0.0 || c.cy_px >= c.height_px) {
    fail(name, "principal point (cx, cy) must lie inside the image");
  }
}

}  // namespace

PinholeCamera parse_camera_text(const std::string& text, const std::string& name) {
  std::string body = text;
  if (body.rfind("%YAML:", 0) == 0) {  // OpenCV FileStorage header, not YAML 1.2
    const auto eol = body.find('\n');
    body = eol == std::string::npos ? std::string() : body.substr(eol + 1);
  }
  YAML::Node root;
  try {
    root = YAML::Load(body);
  } catch (const YAML::Exception& e) {
    fail(name, std::string("not YAML/JSON: ") + e.what());
  }
  if (!root.IsMap()) fail(name, "expected a mapping of camera keys");
  PinholeCamera c;
  if (root["intrinsic_matrix"]) {  // Open3D JSON, column-major
    const auto K = numbers(root, "intrinsic_matrix", 9, name);
    c.fx_px = K[0];
    c.fy_px = K[4];
    c.cx_px = K[6];
    c.cy_px = K[7];
    c.width_px = static_cast<int>(required(root, "width", name));
    c.height_px = static_cast<int>(required(root, "height", name));
  } else if (root["intrinsics"]) {  // Kimera-VIO
    const auto k = numbers(root, "intrinsics", 4, name);
    const auto res = numbers(root, "resolution", 2, name);
    c = {static_cast<int>(res[0]), static_cast<int>(res[1]), k[0], k[1], k[2], k[3]};
  } else {
    c.fx_px = required(root, "fx", name);
    c.fy_px = required(root, "fy", name);
    c.cx_px = required(root, "cx", name);
    c.cy_px = required(root, "cy", name);
    c.width_px = static_cast<int>(required(root, "width", name));
    c.height_px = static_cast<int>(required(root, "height", name));
  }
  check(c, name);
  return c;
}

PinholeCamera load_camera_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) fail(path, "cannot open camera file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_camera_text(ss.str(), path);
}

}  // namespace vigs::tracking
