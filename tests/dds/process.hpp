#pragma once
// Test support: run a helper binary as a second process (fork + exec), capture its stdout,
// wait for it with a timeout (killed on timeout, so a hung peer fails the test, never hangs it).
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace vigs::dds::test {

class ChildProcess {
 public:
  /// env: extra NAME=VALUE entries for the child. merge_stderr: capture stderr too.
  ChildProcess(const std::vector<std::string>& argv, const std::vector<std::string>& env = {},
               bool merge_stderr = false) {
    int fds[2];
    if (pipe(fds) != 0) std::abort();
    pid_ = fork();
    if (pid_ == 0) {
      dup2(fds[1], STDOUT_FILENO);
      if (merge_stderr) dup2(fds[1], STDERR_FILENO);
      close(fds[0]);
      close(fds[1]);
      for (const std::string& e : env) putenv(const_cast<char*>(e.c_str()));
      std::vector<char*> args;
      for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      execv(args[0], args.data());
      _exit(127);
    }
    close(fds[1]);
    out_fd_ = fds[0];
    fcntl(out_fd_, F_SETFL, O_NONBLOCK);
  }
  ~ChildProcess() {
    if (pid_ > 0 && !exited_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
    if (out_fd_ >= 0) close(out_fd_);
  }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// Exit status (WEXITSTATUS), or -1 after killing it at the timeout, -2 when signalled.
  int wait(std::chrono::milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!exited_) {
      drain();
      int status = 0;
      const pid_t r = waitpid(pid_, &status, WNOHANG);
      if (r == pid_) {
        exited_ = true;
        status_ = WIFEXITED(status) ? WEXITSTATUS(status) : -2;
        break;
      }
      if (std::chrono::steady_clock::now() > deadline) {
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
        exited_ = true;
        status_ = -1;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    drain();
    return status_;
  }
  /// Everything the child printed on stdout so far.
  const std::string& output() {
    drain();
    return out_;
  }
  pid_t pid() const { return pid_; }

 private:
  void drain() {
    char buf[4096];
    for (;;) {
      const ssize_t n = read(out_fd_, buf, sizeof buf);
      if (n <= 0) break;
      out_.append(buf, static_cast<std::size_t>(n));
    }
  }
  pid_t pid_ = -1;
  int out_fd_ = -1;
  bool exited_ = false;
  int status_ = 0;
  std::string out_;
};

/// Reads a child's stdout on a thread while a run lasts: a pipe holds 64 KiB (about 50 pose
/// lines), and a full pipe would stall a subscriber's listener and lose the rest. Stop it (or
/// destroy it) before the child's wait().
class OutputDrainer {
 public:
  explicit OutputDrainer(ChildProcess& child)
      : thread_([this, &child] {
          while (running_.load()) {
            (void)child.output();
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
          }
        }) {}
  ~OutputDrainer() { stop(); }
  OutputDrainer(const OutputDrainer&) = delete;
  OutputDrainer& operator=(const OutputDrainer&) = delete;
  void stop() {
    running_.store(false);
    if (thread_.joinable()) thread_.join();
  }

 private:
  std::atomic<bool> running_{true};
  std::thread thread_;
};

}  // namespace vigs::dds::test
