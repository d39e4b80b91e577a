#pragma once
// Each `vigs` subcommand registers itself on the CLI11 app. A subcommand's callback sets
// the process exit code through the shared ExitCode it is given.
#include <CLI/CLI.hpp>

namespace vigs::apps {

struct ExitCode {
  int value = 0;
};

void add_config_command(CLI::App& app, ExitCode& exit_code);
void add_imu_command(CLI::App& app, ExitCode& exit_code);
void add_rgbd_command(CLI::App& app, ExitCode& exit_code);
void add_record_command(CLI::App& app, ExitCode& exit_code);
/// `vigs eval imu`: registered under the shared `eval` group (apps/eval_group.hpp).
void add_eval_imu_command(CLI::App& app, ExitCode& exit_code);
void add_align_command(CLI::App& app, ExitCode& exit_code);
void add_mcap_command(CLI::App& app, ExitCode& exit_code);
void add_simulate_command(CLI::App& app, ExitCode& exit_code);
void add_eval_command(CLI::App& app, ExitCode& exit_code);
void add_eval_image_command(CLI::App& app, ExitCode& exit_code);
void add_render_command(CLI::App& app, ExitCode& exit_code);
void add_map_command(CLI::App& app, ExitCode& exit_code);
void add_replay_command(CLI::App& app, ExitCode& exit_code);
void add_run_command(CLI::App& app, ExitCode& exit_code);
void add_echo_command(CLI::App& app, ExitCode& exit_code);
void add_topics_command(CLI::App& app, ExitCode& exit_code);
void add_import_command(CLI::App& app, ExitCode& exit_code);

}  // namespace vigs::apps
