// `vigs config print [FILE]` and `vigs config check FILE...`.
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "apps/commands.hpp"
#include "core/config/default_config.hpp"
#include "core/config/diagnostics.hpp"
#include "core/config/yaml_loader.hpp"
#include "core/config/yaml_printer.hpp"
#include "drivers/serial_imu/parser_factory.hpp"

namespace vigs::apps {

void add_config_command(CLI::App& app, ExitCode& exit_code) {
  auto* config = app.add_subcommand("config", "Print or check a robot configuration");
  config->require_subcommand(1);

  auto* print = config->add_subcommand(
      "print", "Print the effective configuration (built-in default when no FILE is given)");
  static std::string print_file;
  print->add_option("FILE", print_file, "robot YAML file")->check(CLI::ExistingFile);
  print->callback([&exit_code] {
    try {
      const auto cfg = print_file.empty()
                           ? config::load_config_text(config::default_config_text(),
                                                      std::string(config::kDefaultConfigName))
                           : config::load_config_file(print_file);
      std::cout << "# effective configuration of "
                << (print_file.empty() ? std::string(config::kDefaultConfigName) + " (built-in)"
                                       : print_file)
                << "\n"
                << config::print_config(cfg);
    } catch (const config::ConfigError& e) {
      std::cerr << e.what() << "\n";
      exit_code.value = 1;
    }
  });

  auto* check = config->add_subcommand(
      "check", "Check robot files: unknown keys, wrong types and out-of-range values are errors");
  static std::vector<std::string> check_files;
  check->add_option("FILE", check_files, "robot YAML files")->required();
  check->callback([&exit_code] {
    for (const auto& file : check_files) {
      try {
        const auto cfg = config::load_config_file(file);
        // Rules the schema cannot know: which protocol parsers this binary has.
        try {
          (void)drivers::make_imu_parser(cfg.imu.protocol);
        } catch (const std::invalid_argument& e) {
          std::string what = e.what();
          what = what.substr(what.find(": ") + 2);  // the key is named by the diagnostic
          throw config::ConfigError({config::diagnose_key(file, "imu.protocol", what)});
        }
        std::cout << file << ": ok\n";
      } catch (const config::ConfigError& e) {
        std::cerr << e.what() << "\n";
        std::cerr << file << ": " << e.diagnostics().size() << " error(s)\n";
        exit_code.value = 1;
      }
    }
  });
}

}  // namespace vigs::apps
