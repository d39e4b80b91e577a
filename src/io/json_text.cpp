#include "io/json_text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace vigs::io {
namespace {

void check_finite(const Json& j, std::string& pointer) {
  if (j.is_number_float()) {
    if (!std::isfinite(j.get<double>())) {
      throw JsonNonFiniteError("JSON output: non-finite number at \"" +
                               (pointer.empty() ? std::string("/") : pointer) +
                               "\" (JSON has no NaN/Inf)");
    }
    return;
  }
  const std::size_t len = pointer.size();
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) {
      pointer += '/';
      pointer += key;
      check_finite(value, pointer);
      pointer.resize(len);
    }
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) {
      pointer += '/';
      pointer += std::to_string(i);
      check_finite(j[i], pointer);
      pointer.resize(len);
    }
  }
}

bool is_whole(double v) {
  return std::isfinite(v) && v == std::trunc(v) && std::fabs(v) < 9.007199254740992e15 &&
         !(v == 0.0 && std::signbit(v));
}

// Objects and arrays are laid out here; every scalar (string escaping, number text) is
// nlohmann's own dump().
void append_line(const Json& j, std::string& out) {
  if (j.is_object()) {
    out += '{';
    bool first = true;
    for (const auto& [key, value] : j.items()) {
      if (!first) out += ", ";
      first = false;
      out += Json(key).dump(-1, ' ', false, Json::error_handler_t::replace);
      out += ": ";
      append_line(value, out);
    }
    out += '}';
  } else if (j.is_array()) {
    out += '[';
    for (std::size_t i = 0; i < j.size(); ++i) {
      if (i > 0) out += ", ";
      append_line(j[i], out);
    }
    out += ']';
  } else if (j.is_number_float() && is_whole(j.get<double>())) {
    // A whole double prints as an integer ("fps": 1, not 1.0), as the tools always have.
    out += std::to_string(static_cast<std::int64_t>(j.get<double>()));
  } else {
    out += j.dump(-1, ' ', false, Json::error_handler_t::replace);
  }
}

}  // namespace

Json finite_or_null(double v) {
  return std::isfinite(v) ? Json(v) : Json(nullptr);
}

Json finite_or_null(const std::optional<double>& v) {
  return v ? finite_or_null(*v) : Json(nullptr);
}

Json rounded(double v, int digits) {
  if (!std::isfinite(v)) return Json(v);
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return Json(std::strtod(buf, nullptr));
}

Json fixed(double v, int decimals) {
  if (!std::isfinite(v)) return Json(v);
  char buf[400];  // %f of the largest double has 309 integer digits
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return Json(std::strtod(buf, nullptr));
}

void require_finite(const Json& j) {
  std::string pointer;
  check_finite(j, pointer);
}

std::string json_line(const Json& j) {
  require_finite(j);
  std::string out;
  append_line(j, out);
  return out;
}

std::string json_lines(const Json& j) {
  require_finite(j);
  if (!j.is_object() || j.empty()) return json_line(j);
  std::string out = "{\n";
  bool first = true;
  for (const auto& [key, value] : j.items()) {
    if (!first) out += ",\n";
    first = false;
    out += "  ";
    out += Json(key).dump(-1, ' ', false, Json::error_handler_t::replace);
    out += ": ";
    const bool rows = value.is_array() && std::all_of(value.begin(), value.end(),
                                                      [](const Json& e) { return e.is_object(); });
    if (!rows) {
      append_line(value, out);
      continue;
    }
    out += '[';
    for (std::size_t i = 0; i < value.size(); ++i) {
      out += i > 0 ? ",\n    " : "\n    ";
      append_line(value[i], out);
    }
    out += "\n  ]";
  }
  out += "\n}";
  return out;
}

}  // namespace vigs::io
