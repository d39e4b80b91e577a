#pragma once
#include <string>
#include <string_view>

#include "core/config/diagnostics.hpp"
#include "core/config/robot_config.hpp"

namespace vigs::config {

/// Loads a robot configuration from YAML text. Keys absent from the file keep their
/// declared defaults. Unknown keys, wrong types, out-of-range values and failed
/// cross-field rules are all reported (file, line, column, key) in one ConfigError.
/// `file_name` is only used in diagnostics. Text longer than kMaxConfigBytes is refused before
/// it is parsed (a robot file is a few KiB; yaml-cpp spends hundreds of bytes per node, so a
/// 1 M-element list would take gigabytes), and running out of memory while parsing is a
/// ConfigError too, never an uncaught std::bad_alloc.
RobotConfig load_config_text(std::string_view yaml_text, const std::string& file_name);

/// The largest robot YAML accepted, bytes.
inline constexpr std::size_t kMaxConfigBytes = 1u << 18;

/// Reads `path` and loads it; an unreadable file or one larger than kMaxConfigBytes is a
/// ConfigError naming the path.
RobotConfig load_config_file(const std::string& path);

}  // namespace vigs::config

namespace vigs::config {

/// A diagnostic for a rule checked outside the schema (e.g. `imu.protocol` against the parsers
/// linked into the binary), located at `dotted_key`'s line in `path` when the key is there.
Diagnostic diagnose_key(const std::string& path, const std::string& dotted_key,
                        std::string message);

}  // namespace vigs::config
