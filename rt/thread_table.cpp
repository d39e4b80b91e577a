#include "rt/thread_table.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>

namespace vigs::rt {
namespace {

enum class WarnKind { kName, kScheduling, kAffinity, kMemoryLock, kCount };

std::atomic<bool> g_warned[static_cast<int>(WarnKind::kCount)];

// True the first time it is called for `kind` in this process.
bool first_warning(WarnKind kind) noexcept {
  return !g_warned[static_cast<int>(kind)].exchange(true, std::memory_order_relaxed);
}

const char* error_text(int err, char* buf, std::size_t len) noexcept {
  // glibc's GNU strerror_r (C++ builds define _GNU_SOURCE): returns the message pointer.
  return strerror_r(err, buf, len);
}

void warn(WarnKind kind, const ThreadSpec& spec, const char* what, int err, const char* hint) {
  if (!first_warning(kind)) return;
  char buf[128];
  std::fprintf(stderr,
               "vigs rt: warning: thread '%s': cannot %s: %s. %s Continuing without it "
               "(further warnings of this kind are suppressed).\n",
               spec.name.c_str(), what, error_text(err, buf, sizeof buf), hint);
}

// CAP_IPC_LOCK in the effective set, read from /proc (no libcap dependency).
bool has_cap_ipc_lock() noexcept {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (f == nullptr) return false;
  char line[256];
  unsigned long long caps = 0;
  bool found = false;
  while (std::fgets(line, sizeof line, f) != nullptr) {
    if (std::sscanf(line, "CapEff: %llx", &caps) == 1) {
      found = true;
      break;
    }
  }
  std::fclose(f);
  constexpr int kCapIpcLock = 14;
  return found && ((caps >> kCapIpcLock) & 1u) != 0;
}

}  // namespace

const ThreadSpec& thread_spec(std::string_view name) {
  const ThreadSpec* s = find_thread_spec(name);
  if (s == nullptr)
    throw std::out_of_range("no thread called '" + std::string(name) + "' in kThreadTable");
  return *s;
}

std::string ThreadApplyStatus::describe() const {
  auto part = [](std::string_view what, ApplyResult r, int err) {
    std::string s(what);
    s += ' ';
    s += to_string(r);
    if (r == ApplyResult::kRefused) {
      char buf[128];
      s += " (";
      s += error_text(err, buf, sizeof buf);
      s += ')';
    }
    return s;
  };
  return part("name", name, name_errno) + ", " + part("scheduling", scheduling, scheduling_errno) +
         ", " + part("affinity", affinity, affinity_errno);
}

ThreadApplyStatus apply_thread_spec(const ThreadSpec& spec) noexcept {
  ThreadApplyStatus st;
  const pthread_t self = pthread_self();

  if (!spec.name.view().empty()) {
    const int err = pthread_setname_np(self, spec.name.c_str());
    st.name = err == 0 ? ApplyResult::kApplied : ApplyResult::kRefused;
    st.name_errno = err;
    if (err != 0) warn(WarnKind::kName, spec, "set its name", err, "");
  }

  {
    sched_param param{};
    int policy = spec.sched_idle ? SCHED_IDLE : SCHED_OTHER;
    int err = 0;
    if (spec.sched_fifo_priority > 0) {
      policy = SCHED_FIFO;
      param.sched_priority = spec.sched_fifo_priority;
      if (spec.sched_fifo_priority < sched_get_priority_min(SCHED_FIFO) ||
          spec.sched_fifo_priority > sched_get_priority_max(SCHED_FIFO)) {
        err = EINVAL;
      }
    }
    if (err == 0) err = pthread_setschedparam(self, policy, &param);
    st.scheduling = err == 0 ? ApplyResult::kApplied : ApplyResult::kRefused;
    st.scheduling_errno = err;
    if (err != 0) {
      char what[64];
      std::snprintf(what, sizeof what, "use SCHED_FIFO priority %d", spec.sched_fifo_priority);
      warn(WarnKind::kScheduling, spec, what, err,
           "Real-time priority needs CAP_SYS_NICE or an rtprio limit "
           "(/etc/security/limits.conf, or LimitRTPRIO= in the systemd unit).");
    }
  }

  if (spec.cpu < 0) {
    // Any CPU of the process: a new thread inherits its creator's affinity, and a worker made
    // by a pinned thread (the tracker's team, started on the tracker thread) would otherwise
    // share its creator's one CPU. The process's set is the main thread's (never pinned here).
    cpu_set_t set;
    CPU_ZERO(&set);
    if (sched_getaffinity(getpid(), sizeof set, &set) == 0)
      (void)pthread_setaffinity_np(self, sizeof set, &set);
  } else {
    int err = 0;
    if (spec.cpu >= CPU_SETSIZE) {
      err = EINVAL;
    } else {
      cpu_set_t set;
      CPU_ZERO(&set);
      CPU_SET(static_cast<std::size_t>(spec.cpu), &set);
      err = pthread_setaffinity_np(self, sizeof set, &set);
    }
    st.affinity = err == 0 ? ApplyResult::kApplied : ApplyResult::kRefused;
    st.affinity_errno = err;
    if (err != 0) {
      char what[64];
      std::snprintf(what, sizeof what, "pin itself to CPU %d", spec.cpu);
      warn(WarnKind::kAffinity, spec, what, err,
           "The CPU may be absent or outside this process's cpuset.");
    }
  }
  return st;
}

MemoryLockStatus lock_memory() noexcept {
  MemoryLockStatus st;
  rlimit lim{};
  const bool unlimited = getrlimit(RLIMIT_MEMLOCK, &lim) == 0 && lim.rlim_cur == RLIM_INFINITY;
  int err = 0;
  if (!unlimited && !has_cap_ipc_lock()) {
    err = EPERM;
  } else if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
    err = errno;
  }
  st.result = err == 0 ? ApplyResult::kApplied : ApplyResult::kRefused;
  st.error = err;
  if (err != 0 && first_warning(WarnKind::kMemoryLock)) {
    char buf[128];
    std::fprintf(stderr,
                 "vigs rt: warning: cannot lock memory (mlockall): %s. Needs CAP_IPC_LOCK or "
                 "RLIMIT_MEMLOCK=unlimited (LimitMEMLOCK=infinity). Continuing unlocked: page "
                 "faults may add latency.\n",
                 error_text(err, buf, sizeof buf));
  }
  return st;
}

}  // namespace vigs::rt
