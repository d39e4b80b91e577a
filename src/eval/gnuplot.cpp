#include "eval/gnuplot.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <vector>

extern char** environ;

namespace vigs::eval {

std::string run_gnuplot(const std::string& script_path, const std::string& log_path,
                        const std::string& work_dir) {
  // The child changes folder first (glibc >= 2.29), then opens these: made absolute here.
  std::error_code ec;
  std::string script = std::filesystem::absolute(script_path, ec).string();
  if (ec) script = script_path;
  std::string log = std::filesystem::absolute(log_path, ec).string();
  if (ec) log = log_path;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!work_dir.empty()) posix_spawn_file_actions_addchdir_np(&actions, work_dir.c_str());
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::string prog = "gnuplot";
  std::vector<char*> argv = {prog.data(), script.data(), nullptr};
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, "gnuplot", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    return std::string("cannot run gnuplot (install gnuplot-nox): ") + std::strerror(rc);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return std::string("waitpid failed: ") + std::strerror(errno);
  }
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    return "gnuplot failed on " + script_path + " (see " + log_path + ")";
  }
  return "";
}

}  // namespace vigs::eval
