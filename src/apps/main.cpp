// vigs: the one VIGS binary. Subcommands are registered in commands.hpp.
#include <CLI/CLI.hpp>

#include "apps/commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "VIGS: real-time RGB-D + IMU SLAM. IMU-seeded Generalized ICP tracking, a CPU 3D Gaussian "
      "Splatting map, poses on DDS."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "vigs 0.1.0");

  vigs::apps::ExitCode exit_code;
  vigs::apps::add_config_command(app, exit_code);
  vigs::apps::add_imu_command(app, exit_code);
  vigs::apps::add_rgbd_command(app, exit_code);
  vigs::apps::add_record_command(app, exit_code);
  vigs::apps::add_eval_imu_command(app, exit_code);
  vigs::apps::add_align_command(app, exit_code);
  vigs::apps::add_mcap_command(app, exit_code);
  vigs::apps::add_simulate_command(app, exit_code);
  vigs::apps::add_eval_command(app, exit_code);
  vigs::apps::add_eval_image_command(app, exit_code);
  vigs::apps::add_render_command(app, exit_code);
  vigs::apps::add_map_command(app, exit_code);
  vigs::apps::add_replay_command(app, exit_code);
  vigs::apps::add_echo_command(app, exit_code);
  vigs::apps::add_topics_command(app, exit_code);

  CLI11_PARSE(app, argc, argv);
  return exit_code.value;
}
