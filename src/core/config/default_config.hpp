#pragma once
#include <string_view>

namespace vigs::config {

/// firmware_config/robots/sim_office.yaml, compiled into the binary so that `vigs` runs on
/// its built-in default from any working directory.
std::string_view default_config_text();
inline constexpr std::string_view kDefaultConfigName = "firmware_config/robots/sim_office.yaml";

}  // namespace vigs::config
