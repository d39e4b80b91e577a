#pragma once
// What a reader of a recording says about damage: every tool that reads an MCAP file and goes
// on past damage (eval, `mcap oni`, `replay --allow-truncated`) reports the first problem and
// how much it used, on stderr and in its JSON, so damage is never silent.
#include <cstdint>
#include <cstdio>
#include <string>

#include "io/mcap/mcap_reader.hpp"

namespace vigs::io::mcap {

struct DamageReport {
  std::size_t issues = 0;    ///< problems the reader found (0 = intact as far as read)
  std::string kind;          ///< of the first: truncated, corrupt, crc mismatch, unsupported
  std::uint64_t offset = 0;  ///< byte offset of the first
  std::string message;       ///< the first, naming the file and offset
  bool damaged() const { return issues > 0; }
};

inline DamageReport damage_of(const McapReader& reader) {
  DamageReport d;
  d.issues = reader.issues().size();
  if (d.issues > 0) {
    const ReadIssue& first = reader.issues().front();
    d.kind = to_string(first.kind);
    d.offset = first.offset;
    d.message = first.message;
  }
  return d;
}

/// One line for stderr: "damaged recording (truncated at byte N): MESSAGE; used WHAT".
inline std::string damage_warning(const DamageReport& d, const std::string& used) {
  return "damaged recording (" + d.kind + " at byte " + std::to_string(d.offset) +
         "): " + d.message + "; used " + used;
}

/// JSON object {"issues", "kind", "offset", "message", "used"} for the tools' reports, or
/// null when intact. `used` is what the tool used, e.g. "412 messages up to t = 20.55 s".
inline std::string damage_json(const DamageReport& d, const std::string& used) {
  if (!d.damaged()) return "null";
  const auto quote = [](const std::string& text) {
    std::string out = "\"";
    for (const char c : text) {
      if (c == '"' || c == '\\') {
        out += '\\';
        out += c;
      } else if (static_cast<unsigned char>(c) < 0x20) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
        out += buf;
      } else {
        out += c;
      }
    }
    return out + "\"";
  };
  return "{\"issues\": " + std::to_string(d.issues) + ", \"kind\": " + quote(d.kind) +
         ", \"offset\": " + std::to_string(d.offset) + ", \"message\": " + quote(d.message) +
         ", \"used\": " + quote(used) + "}";
}

}  // namespace vigs::io::mcap
