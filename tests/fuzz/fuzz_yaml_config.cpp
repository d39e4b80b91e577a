// libFuzzer target: config::load_config_text on any text returns a RobotConfig or throws
// ConfigError with diagnostics (file, line, column, key); never another exception (an uncaught
// YAML::Exception or std::bad_alloc is a finding), a crash or a hang. Seeds: the robot files in
// firmware_config/robots (fuzz_file_seeds copies them).
#include <cstdint>
#include <string_view>

#include "core/config/diagnostics.hpp"
#include "core/config/yaml_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    (void)vigs::config::load_config_text(text, "fuzz.yaml");
  } catch (const vigs::config::ConfigError& e) {
    if (e.diagnostics().empty()) __builtin_trap();  // an error must say what is wrong
  }
  return 0;
}
