// Every VIGS thread in one table: name, SCHED_FIFO priority, CPU, period.
//
// Target: a 2-core robot computer. CPU 0 takes the sensor drivers and I/O threads, which mostly
// sleep in read()/poll() and run briefly when data arrives; CPU 1 is kept for the tracker, the
// one fixed-rate task with a hard budget (one camera period). The mapper runs at normal priority
// on any CPU and soaks up whatever time the real-time threads leave.
// Priorities (SCHED_FIFO 1..99, higher runs first): the drivers are highest because they own
// timestamps and small kernel buffers (the trigger edge stamp is the most timing-critical, then
// the IMU at up to 1 kHz, then the camera); the tracker is below them so a frame arriving never
// waits for a GICP solve. DDS and recording are not real-time safe and stay SCHED_OTHER. 99 is
// left to the kernel's own watchdog/migration threads.
//
// apply_thread_spec() never fails: where the OS refuses (no CAP_SYS_NICE / rtprio limit, CPU not
// present, ...) it prints one warning per kind to stderr and the thread runs on with what it has.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

#include "rt/clock.hpp"

namespace vigs::rt {

// A thread name as Linux stores it: at most 15 characters. Constructing a longer one is a compile
// error in a constant expression (the thread table) and truncates at run time.
class ThreadName {
 public:
  static constexpr std::size_t kMaxLength = 15;

  constexpr ThreadName() = default;
  constexpr ThreadName(const char* s) : ThreadName(std::string_view(s)) {}  // NOLINT: implicit
  constexpr ThreadName(std::string_view s) {                                // NOLINT: implicit
    if (s.size() > kMaxLength) {
      if (std::is_constant_evaluated()) throw std::length_error("thread name over 15 characters");
      s = s.substr(0, kMaxLength);
    }
    for (std::size_t i = 0; i < s.size(); ++i) chars_[i] = s[i];
    size_ = s.size();
  }

  [[nodiscard]] constexpr std::string_view view() const noexcept { return {chars_.data(), size_}; }
  [[nodiscard]] constexpr const char* c_str() const noexcept { return chars_.data(); }
  friend constexpr bool operator==(const ThreadName& a, const ThreadName& b) noexcept {
    return a.view() == b.view();
  }

 private:
  std::array<char, kMaxLength + 1> chars_{};  // always NUL-terminated
  std::size_t size_ = 0;
};

struct ThreadSpec {
  ThreadName name;              // pthread name, <= 15 chars (shown by top -H, ps -L, gdb)
  int sched_fifo_priority = 0;  // 1..99: SCHED_FIFO at this priority; 0: SCHED_OTHER
  int cpu = -1;                 // pin to this CPU index; -1: any CPU of the process
  std::int64_t period_ns = 0;   // > 0: a PeriodicTask with this period; 0: aperiodic (event driven)
  // With priority 0 only: SCHED_IDLE instead of SCHED_OTHER. For best-effort work that every
  // other thread on the CPU goes before, SCHED_OTHER ones included (the kernel's pty and USB
  // workers, OpenNI2's reader, the DDS publisher), not only the SCHED_FIFO ones.
  bool sched_idle = false;
};

// Worker teams (rt/worker_team.hpp): an entry `<task>_w1` is member 1 of `<task>`'s team (the
// task's own thread is member 0). On the 2-core target a team has two members, so `tracker_w1`
// takes the tracker's priority on the CPU the tracker does not use: it runs the other half of
// each parallel region, preempted only by the drivers. Members beyond 1 (more tracking.num_threads
// or mapping.threads than CPUs) are named `<task>_w<m>`, with the same priority and no pinning.
inline constexpr std::array<ThreadSpec, 10> kThreadTable{{
    // Edge stamps from the GPIO frame-sync line; wakes on each line event.
    {.name = "gpio_trigger", .sched_fifo_priority = 85, .cpu = 0, .period_ns = 0},
    // Serial IMU: termios reads, parses samples, pushes ImuSample (up to 1 kHz).
    {.name = "imu_driver", .sched_fifo_priority = 80, .cpu = 0, .period_ns = 0},
    // OpenNI2 / V4L2 RGB-D frames into the FramePool; pushes FrameHandle.
    {.name = "rgbd_driver", .sched_fifo_priority = 75, .cpu = 0, .period_ns = 0},
    // Fixed rate = camera rate (20 Hz): preintegrate, GICP, pose out, keyframe decision.
    {.name = "tracker", .sched_fifo_priority = 60, .cpu = 1, .period_ns = ms_to_ns(50)},
    // The tracker's worker team member 1: preprocessing (kNN covariances) and GICP linearisation.
    {.name = "tracker_w1", .sched_fifo_priority = 60, .cpu = 0, .period_ns = 0},
    // Gaussian map: insert keyframes, N optimisation iterations per tick, prune. Best effort
    // (SCHED_IDLE): it takes only what no other thread wants, so it never delays the serial
    // bytes' kernel worker, the camera's reader or the publisher (each SCHED_OTHER). Its period
    // (mapping.rate_hz, default 5 ms) is shorter than an iteration: with keyframes it runs back
    // to back on the CPU the others leave (at 100 ms a third of both CPUs stayed idle).
    {.name = "mapper",
     .sched_fifo_priority = 0,
     .cpu = -1,
     .period_ns = ms_to_ns(5),
     .sched_idle = true},
    // The mapper's worker team member 1: rasterizer tiles, SSIM rows.
    {.name = "mapper_w1", .sched_fifo_priority = 0, .cpu = -1, .period_ns = 0, .sched_idle = true},
    // Drains the pose ring and publishes on DDS (not real-time safe: SCHED_OTHER). 500 Hz polling
    // adds at most 2 ms to a 20 Hz pose (an empty poll is one ring read).
    {.name = "dds_pub", .sched_fifo_priority = 0, .cpu = 0, .period_ns = ms_to_ns(2)},
    // Drains its tap rings into MCAP (zstd, disk I/O): SCHED_OTHER, any CPU.
    {.name = "recorder", .sched_fifo_priority = 0, .cpu = -1, .period_ns = ms_to_ns(20)},
    // `vigs run --through-drivers` only: writes the recording's IMU bytes into the pty on time.
    // It stands in for the sensor, which shares no CPU with the pipeline: above every thread.
    {.name = "sensor_replay", .sched_fifo_priority = 90, .cpu = -1, .period_ns = 0},
}};

// The table entry called `name`, or nullptr.
[[nodiscard]] constexpr const ThreadSpec* find_thread_spec(std::string_view name) noexcept {
  for (const ThreadSpec& s : kThreadTable) {
    if (s.name.view() == name) return &s;
  }
  return nullptr;
}

// The table entry called `name`; throws std::out_of_range for an unknown name (a start-up bug).
[[nodiscard]] const ThreadSpec& thread_spec(std::string_view name);

namespace detail {
constexpr bool thread_table_valid() {
  for (std::size_t i = 0; i < kThreadTable.size(); ++i) {
    const ThreadSpec& s = kThreadTable[i];
    if (s.name.view().empty() || s.sched_fifo_priority < 0 || s.sched_fifo_priority > 98) {
      return false;
    }
    if (s.cpu < -1 || s.period_ns < 0) return false;
    for (std::size_t j = i + 1; j < kThreadTable.size(); ++j) {
      if (kThreadTable[j].name == s.name) return false;
    }
  }
  return true;
}
}  // namespace detail
static_assert(detail::thread_table_valid(), "thread names unique, priorities 0..98, cpu >= -1");
namespace detail {
// Every `<task>_w1` entry belongs to a table entry `<task>`, is aperiodic (it runs when its task
// dispatches), has its task's priority (a lower one would let the drivers' CPU starve half of the
// task's parallel regions; a higher one would preempt the task's own drivers) and, when both are
// pinned, sits on another CPU (two members on one CPU only take turns).
constexpr bool worker_entries_valid() {
  for (const ThreadSpec& w : kThreadTable) {
    const std::string_view name = w.name.view();
    if (name.size() < 4 || name.substr(name.size() - 3) != "_w1") continue;
    const ThreadSpec* task = find_thread_spec(name.substr(0, name.size() - 3));
    if (task == nullptr || w.period_ns != 0) return false;
    if (w.sched_fifo_priority != task->sched_fifo_priority) return false;
    if (w.cpu >= 0 && task->cpu >= 0 && w.cpu == task->cpu) return false;
  }
  return true;
}
}  // namespace detail
static_assert(detail::worker_entries_valid(),
              "each <task>_w1 worker has a <task> entry, its priority and another CPU");
static_assert(find_thread_spec("tracker_w1") != nullptr && find_thread_spec("mapper_w1") != nullptr,
              "the tracker's and the mapper's worker teams are in the table");
static_assert(find_thread_spec("tracker")->period_ns == ms_to_ns(50), "tracker runs at 20 Hz");
static_assert(find_thread_spec("imu_driver")->sched_fifo_priority >
                  find_thread_spec("tracker")->sched_fifo_priority,
              "drivers preempt the tracker");

// `spec` as the rt: configuration allows it: priority 0 (SCHED_OTHER, never SCHED_IDLE) unless
// realtime_priorities,
// cpu -1 unless pin_cpus. Applied by whoever builds a thread from the table (the live pipeline
// from rt.realtime_priorities / rt.pin_cpus; tools and tests leave both off).
[[nodiscard]] constexpr ThreadSpec apply_policy(ThreadSpec spec, bool realtime_priorities,
                                                bool pin_cpus) noexcept {
  if (!realtime_priorities) {
    spec.sched_fifo_priority = 0;
    spec.sched_idle = false;
  }
  if (!pin_cpus) spec.cpu = -1;
  return spec;
}

enum class ApplyResult : std::uint8_t {
  kNotRequested,  // nothing asked (cpu == -1)
  kApplied,       // in effect on the calling thread
  kRefused,       // the OS said no; see the matching *_errno; a warning was printed (once per kind)
};

[[nodiscard]] constexpr std::string_view to_string(ApplyResult r) noexcept {
  switch (r) {
    case ApplyResult::kNotRequested:
      return "not requested";
    case ApplyResult::kApplied:
      return "applied";
    case ApplyResult::kRefused:
      return "refused";
  }
  return "?";
}

struct ThreadApplyStatus {
  ApplyResult name = ApplyResult::kNotRequested;
  int name_errno = 0;
  // SCHED_FIFO at the requested priority, or SCHED_OTHER (SCHED_IDLE) when the priority is 0.
  ApplyResult scheduling = ApplyResult::kNotRequested;
  int scheduling_errno = 0;
  ApplyResult affinity = ApplyResult::kNotRequested;
  int affinity_errno = 0;

  [[nodiscard]] bool fully_applied() const noexcept {
    return name != ApplyResult::kRefused && scheduling != ApplyResult::kRefused &&
           affinity != ApplyResult::kRefused;
  }
  // "name applied, scheduling refused (EPERM), affinity applied" (not real-time safe).
  [[nodiscard]] std::string describe() const;
};

// Applies `spec` to the calling thread: pthread_setname_np, SCHED_FIFO/SCHED_OTHER/SCHED_IDLE via
// pthread_setschedparam, pthread_setaffinity_np. Never throws, never aborts.
ThreadApplyStatus apply_thread_spec(const ThreadSpec& spec) noexcept;

struct MemoryLockStatus {
  ApplyResult result = ApplyResult::kNotRequested;
  int error = 0;
};

// mlockall(MCL_CURRENT | MCL_FUTURE) so that no real-time thread ever takes a page fault to disk.
// Call once at start-up, before creating threads and pools. Refused (with one warning) when the
// process lacks CAP_IPC_LOCK and RLIMIT_MEMLOCK is finite: a successful MCL_FUTURE under a small
// limit would make later allocations fail, which is worse than running unlocked.
MemoryLockStatus lock_memory() noexcept;

}  // namespace vigs::rt
