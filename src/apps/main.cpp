// vigs: the one VIGS binary. Subcommands are registered in commands.hpp.
#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>

#include "apps/commands.hpp"

namespace {

/// Failed writes are errors: a report lost to a full disk or /dev/full must not exit 0. Every
/// command prints through stdout (std::cout is synced with it), so one check covers them all.
int checked_exit(int code) {
  errno = 0;
  std::cout.flush();
  if (!std::cout || std::fflush(stdout) != 0 || std::ferror(stdout)) {
    std::fprintf(stderr, "vigs: cannot write standard output: %s\n",
                 errno != 0 ? std::strerror(errno) : "write error");
    return 1;
  }
  return code;
}

}  // namespace

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
  vigs::apps::add_run_command(app, exit_code);
  vigs::apps::add_echo_command(app, exit_code);
  vigs::apps::add_topics_command(app, exit_code);
  vigs::apps::add_import_command(app, exit_code);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every bad flag or value (including a non-finite number)
    // is a usage error with exit code 1, as every other input error.
    return checked_exit(app.exit(e) == 0 ? 0 : 1);
  }
  return checked_exit(exit_code.value);
}
