#pragma once
// damage_json as an io::Json object, for the reports built with io::Json (json_text.hpp):
// {"issues", "kind", "offset", "message", "used"}, or null when the recording is intact.
#include <string>

#include "io/json_text.hpp"
#include "io/mcap/damage_report.hpp"

namespace vigs::io::mcap {

inline Json damage_object(const DamageReport& d, const std::string& used) {
  if (!d.damaged()) return Json(nullptr);
  Json j;
  j["issues"] = d.issues;
  j["kind"] = d.kind;
  j["offset"] = d.offset;
  j["message"] = d.message;
  j["used"] = used;
  return j;
}

}  // namespace vigs::io::mcap
