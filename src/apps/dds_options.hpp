#pragma once
// The DDS configuration of `vigs echo` and `vigs topics`: the robot YAML's dds: section (or the
// built-in default), with --domain overriding dds.domain_id.
#include <limits>
#include <string>

#include "core/config/default_config.hpp"
#include "core/config/yaml_loader.hpp"
#include "dds/dds_config.hpp"

namespace vigs::apps {

inline constexpr int kNoDomainOverride = std::numeric_limits<int>::min();

inline dds::DdsConfig load_dds_config(const std::string& config_file, int domain_override) {
  config::DdsSettings s = config_file.empty()
                              ? config::load_config_text(config::default_config_text(),
                                                         std::string(config::kDefaultConfigName))
                                    .dds
                              : config::load_config_file(config_file).dds;
  if (domain_override != kNoDomainOverride) s.domain_id = domain_override;
  return dds::resolve_dds_config(s, config_file);
}

}  // namespace vigs::apps
