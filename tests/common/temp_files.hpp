#pragma once
// Test support: names for the files a test writes in ::testing::TempDir(), removed again.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace vigs::test {

/// Hands out paths `TempDir()/PREFIX_PID_NAME` and removes each of them (file or folder, written
/// by the test or by a process it ran) when it is destroyed: also after a failed ASSERT or an
/// exception. Kept as a function-local static (see temp_path below), that is at the test
/// program's exit; ctest runs every test in a process of its own, so after every test. Only the
/// process that made it removes anything (a forked child exiting normally does not).
class TempFiles {
 public:
  explicit TempFiles(const std::string& prefix)
      : prefix_(::testing::TempDir() + "/" + prefix + "_" + std::to_string(::getpid()) + "_"),
        owner_(::getpid()) {}
  ~TempFiles() {
    if (::getpid() != owner_) return;
    for (const std::string& p : paths_) {
      std::error_code ec;  // already gone or never written: nothing to do
      std::filesystem::remove_all(p, ec);
    }
  }
  TempFiles(const TempFiles&) = delete;
  TempFiles& operator=(const TempFiles&) = delete;

  /// The path for `name`, removed with this object.
  std::string path(const std::string& name) {
    paths_.push_back(prefix_ + name);
    return paths_.back();
  }

 private:
  std::string prefix_;
  pid_t owner_;
  std::vector<std::string> paths_;
};

}  // namespace vigs::test
