#include "rt/thread_table.hpp"

#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <set>
#include <stdexcept>
#include <stop_token>
#include <string>
#include <thread>

#include "rt/rt_thread.hpp"

namespace vigs::rt {
namespace {

std::string current_thread_name() {
  char buf[16] = {};
  pthread_getname_np(pthread_self(), buf, sizeof buf);
  return buf;
}

// Runs apply_thread_spec on a fresh std::thread (so the test's own thread keeps its settings)
// and checks that the status matches what the OS reports.
void check_apply(const ThreadSpec& spec) {
  std::thread t([&spec] {
    const ThreadApplyStatus st = apply_thread_spec(spec);
    SCOPED_TRACE(st.describe());
    EXPECT_EQ(st.name, ApplyResult::kApplied);
    EXPECT_EQ(current_thread_name(), std::string(spec.name.view()));

    int policy = -1;
    sched_param param{};
    ASSERT_EQ(pthread_getschedparam(pthread_self(), &policy, &param), 0);
    if (st.scheduling == ApplyResult::kApplied) {
      EXPECT_EQ(policy, spec.sched_fifo_priority > 0 ? SCHED_FIFO
                        : spec.sched_idle            ? SCHED_IDLE
                                                     : SCHED_OTHER);
      EXPECT_EQ(param.sched_priority, spec.sched_fifo_priority);
    } else {
      EXPECT_EQ(st.scheduling, ApplyResult::kRefused);
      EXPECT_NE(st.scheduling_errno, 0);
      EXPECT_EQ(policy, SCHED_OTHER);
    }

    cpu_set_t set;
    CPU_ZERO(&set);
    ASSERT_EQ(pthread_getaffinity_np(pthread_self(), sizeof set, &set), 0);
    if (spec.cpu < 0) {
      EXPECT_EQ(st.affinity, ApplyResult::kNotRequested);
    } else if (st.affinity == ApplyResult::kApplied) {
      EXPECT_EQ(CPU_COUNT(&set), 1);
      EXPECT_TRUE(CPU_ISSET(static_cast<std::size_t>(spec.cpu), &set));
    } else {
      EXPECT_EQ(st.affinity, ApplyResult::kRefused);
      EXPECT_NE(st.affinity_errno, 0);
    }
  });
  t.join();
}

TEST(ThreadTable, HoldsEveryVigsThread) {
  std::set<std::string_view> names;
  for (const ThreadSpec& s : kThreadTable) {
    names.insert(s.name.view());
    EXPECT_LE(s.name.view().size(), ThreadName::kMaxLength);
  }
  EXPECT_EQ(names, (std::set<std::string_view>{"rgbd_driver", "imu_driver", "gpio_trigger",
                                               "tracker", "tracker_w1", "mapper", "mapper_w1",
                                               "dds_pub", "recorder", "sensor_replay"}));
  EXPECT_EQ(thread_spec("tracker_w1").sched_fifo_priority,
            thread_spec("tracker").sched_fifo_priority);
  EXPECT_NE(thread_spec("tracker_w1").cpu, thread_spec("tracker").cpu);
  const ThreadSpec off = apply_policy(thread_spec("tracker"), false, false);
  EXPECT_EQ(off.sched_fifo_priority, 0);
  EXPECT_EQ(off.cpu, -1);
  EXPECT_EQ(off.period_ns, thread_spec("tracker").period_ns);
  EXPECT_EQ(apply_policy(thread_spec("tracker"), true, true).cpu, thread_spec("tracker").cpu);
  EXPECT_EQ(thread_spec("tracker").period_ns, ms_to_ns(50));
  EXPECT_GT(thread_spec("mapper").period_ns, 0);
  // The mapper's team is best effort; nothing else is, and without real-time priorities no
  // thread changes class at all.
  for (const ThreadSpec& s : kThreadTable) {
    EXPECT_EQ(s.sched_idle, s.name.view().starts_with("mapper")) << s.name.view();
    EXPECT_FALSE(apply_policy(s, false, true).sched_idle);
    EXPECT_EQ(apply_policy(s, true, false).sched_idle, s.sched_idle);
  }
  EXPECT_GT(thread_spec("rgbd_driver").sched_fifo_priority,
            thread_spec("tracker").sched_fifo_priority);
  EXPECT_NE(thread_spec("tracker").cpu, thread_spec("imu_driver").cpu);
  EXPECT_EQ(find_thread_spec("no_such_thread"), nullptr);
  EXPECT_THROW((void)thread_spec("no_such_thread"), std::out_of_range);
}

TEST(ThreadTable, ThreadNamesAreTruncatedAtRunTime) {
  const ThreadName n(std::string_view("a_much_too_long_thread_name"));
  EXPECT_EQ(n.view(), "a_much_too_long");
  EXPECT_EQ(std::strlen(n.c_str()), ThreadName::kMaxLength);
  constexpr ThreadName k("tracker");
  static_assert(k.view() == "tracker");
}

TEST(ThreadTable, ApplyEveryTableEntryNeverFails) {
  for (const ThreadSpec& s : kThreadTable) {
    SCOPED_TRACE(std::string(s.name.view()));
    check_apply(s);
  }
}

// SCHED_IDLE needs no privilege: a best-effort thread gets it wherever the pipeline runs.
TEST(ThreadTable, BestEffortThreadsRunUnderSchedIdle) {
  const ThreadSpec idle{.name = "t_idle", .sched_fifo_priority = 0, .cpu = -1, .sched_idle = true};
  std::thread t([&] {
    const ThreadApplyStatus st = apply_thread_spec(idle);
    EXPECT_EQ(st.scheduling, ApplyResult::kApplied);
    EXPECT_EQ(sched_getscheduler(0), SCHED_IDLE);
  });
  t.join();
}

// cpu -1 means any CPU of the process, also for a thread started by a pinned one (which it
// would otherwise inherit: the tracker's worker team is started on the pinned tracker thread).
TEST(ThreadTable, UnpinnedThreadStartedByAPinnedOneGetsEveryCpu) {
  cpu_set_t all;
  CPU_ZERO(&all);
  ASSERT_EQ(sched_getaffinity(getpid(), sizeof all, &all), 0);
  if (CPU_COUNT(&all) < 2) GTEST_SKIP() << "one CPU";
  int first = 0;
  while (!CPU_ISSET(static_cast<std::size_t>(first), &all)) ++first;
  const ThreadSpec pinned{.name = "t_pinned", .sched_fifo_priority = 0, .cpu = first};
  const ThreadSpec any{.name = "t_any", .sched_fifo_priority = 0, .cpu = -1};
  int child_cpus = 0;
  RtThread parent(pinned, [&] {
    RtThread child(any, [&] {
      cpu_set_t set;
      CPU_ZERO(&set);
      if (pthread_getaffinity_np(pthread_self(), sizeof set, &set) == 0)
        child_cpus = CPU_COUNT(&set);
    });
    child.join();
  });
  parent.join();
  EXPECT_EQ(parent.status().affinity, ApplyResult::kApplied);
  EXPECT_EQ(child_cpus, CPU_COUNT(&all));
}

TEST(ThreadTable, RefusalsAreReportedNotFatal) {
  // A CPU far beyond any machine, one beyond CPU_SETSIZE, and a priority out of range.
  const ThreadSpec absent_cpu{.name = "t_absent_cpu", .sched_fifo_priority = 0, .cpu = 1000};
  const ThreadSpec huge_cpu{.name = "t_huge_cpu", .sched_fifo_priority = 0, .cpu = 1 << 20};
  const ThreadSpec bad_prio{.name = "t_bad_prio", .sched_fifo_priority = 150, .cpu = -1};
  std::thread t([&] {
    const ThreadApplyStatus a = apply_thread_spec(absent_cpu);
    EXPECT_EQ(a.affinity, ApplyResult::kRefused);
    EXPECT_EQ(a.affinity_errno, EINVAL);
    EXPECT_FALSE(a.fully_applied());
    const ThreadApplyStatus b = apply_thread_spec(huge_cpu);
    EXPECT_EQ(b.affinity, ApplyResult::kRefused);
    const ThreadApplyStatus c = apply_thread_spec(bad_prio);
    EXPECT_EQ(c.scheduling, ApplyResult::kRefused);
    EXPECT_EQ(c.scheduling_errno, EINVAL);
    EXPECT_NE(c.describe().find("scheduling refused"), std::string::npos) << c.describe();
  });
  t.join();
}

TEST(ThreadTable, LockMemoryNeverFails) {
  const MemoryLockStatus st = lock_memory();
  EXPECT_NE(st.result, ApplyResult::kNotRequested);
  if (st.result == ApplyResult::kApplied) {
    munlockall();  // leave the test process as it was
  } else {
    EXPECT_NE(st.error, 0);
  }
}

TEST(RtThread, RunsTheBodyWithItsSpecAndJoins) {
  std::atomic<bool> ran{false};
  std::string name_inside;
  const ThreadSpec spec{.name = "t_rt_thread", .sched_fifo_priority = 0, .cpu = 0};
  {
    RtThread t(spec, [&] {
      name_inside = current_thread_name();
      ran.store(true);
    });
    EXPECT_EQ(t.status().name, ApplyResult::kApplied);
    EXPECT_EQ(t.spec().name.view(), "t_rt_thread");
    t.join();
    EXPECT_FALSE(t.joinable());
  }
  EXPECT_TRUE(ran.load());
  EXPECT_EQ(name_inside, "t_rt_thread");
}

TEST(RtThread, DestructorStopsAndJoinsAStopTokenBody) {
  std::atomic<int> loops{0};
  std::atomic<bool> exited{false};
  {
    RtThread t(ThreadSpec{.name = "t_rt_stop"}, [&](std::stop_token stop) {
      while (!stop.stop_requested()) {
        loops.fetch_add(1);
        std::this_thread::sleep_for(std::chrono::microseconds(100));
      }
      exited.store(true);
    });
    while (loops.load() < 3) std::this_thread::sleep_for(std::chrono::microseconds(100));
  }  // ~RtThread: request_stop + join
  EXPECT_TRUE(exited.load());
}

}  // namespace
}  // namespace vigs::rt
