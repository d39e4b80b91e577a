#pragma once
#include <string>

#include "core/config/robot_config.hpp"

namespace vigs::config {

/// The effective configuration as YAML that load_config_text() accepts again, each field
/// annotated with its unit, valid range and meaning.
std::string print_config(RobotConfig config);

}  // namespace vigs::config
