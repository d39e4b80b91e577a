#pragma once
// ShmJanitor: Fast DDS's shared-memory transport creates files in /dev/shm (fastrtps_<id>
// segments, fastrtps_port<N> queues, their *_el liveness files and sem.*_mutex semaphores). A
// clean exit removes them; a killed process leaves them. A test holds a janitor for its whole
// run: at the end it removes the fastrtps entries that appeared while it ran and that no live
// process uses. A live user holds a shared flock on <entry>_el, so an entry whose _el file this
// process can lock exclusively (or that has none) is dead; entries of other, concurrently
// running DDS processes are left alone.
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <set>
#include <string>
#include <system_error>

namespace vigs::dds::test {

class ShmJanitor {
 public:
  ShmJanitor() : before_(list()) {}
  ~ShmJanitor() { clean(); }
  ShmJanitor(const ShmJanitor&) = delete;
  ShmJanitor& operator=(const ShmJanitor&) = delete;

  /// Removes what appeared since construction; returns how many entries it removed.
  int clean() {
    int n = 0;
    for (const std::string& name : list()) {
      if (before_.count(name) != 0 || in_use(name)) continue;
      std::error_code ec;
      if (std::filesystem::remove(std::filesystem::path("/dev/shm") / name, ec)) ++n;
    }
    return n;
  }

  static std::set<std::string> list() {
    std::set<std::string> out;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator("/dev/shm", ec)) {
      const std::string name = e.path().filename().string();
      if (name.rfind("fastrtps_", 0) == 0 || name.rfind("sem.fastrtps_", 0) == 0) {
        out.insert(name);
      }
    }
    return out;
  }

 private:
  static bool in_use(std::string name) {
    const std::string mutex_suffix = "_mutex";
    if (name.rfind("sem.", 0) == 0 && name.size() > 4 + mutex_suffix.size() &&
        name.compare(name.size() - mutex_suffix.size(), mutex_suffix.size(), mutex_suffix) == 0) {
      name = name.substr(4, name.size() - 4 - mutex_suffix.size());
    }
    if (name.size() > 3 && name.compare(name.size() - 3, 3, "_el") == 0) {
      name.resize(name.size() - 3);
    }
    const std::string el = "/dev/shm/" + name + "_el";
    const int fd = open(el.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return false;
    const bool locked_by_someone = flock(fd, LOCK_EX | LOCK_NB) != 0;
    close(fd);  // releases our lock, if we got it
    return locked_by_someone;
  }

  std::set<std::string> before_;
};

}  // namespace vigs::dds::test
