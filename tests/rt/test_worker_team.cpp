// rt::WorkerTeam: every index runs exactly once on its fixed member, exceptions reach the caller,
// the futex hand-off survives a two-thread stress (TSan runs this file), worker threads carry the
// thread table's names.
#include "rt/worker_team.hpp"

#include <gtest/gtest.h>
#include <pthread.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "rt_test_support.hpp"

namespace vigs::rt {
namespace {

TEST(WorkerTeam, EveryIndexRunsExactlyOnceOnItsFixedMember) {
  for (int size : {1, 2, 3, 4}) {
    WorkerTeam team(size);
    ASSERT_EQ(team.size(), size);
    std::vector<int> hits(1001, 0);
    std::vector<int> owner(1001, -1);
    for (int round = 0; round < 200; ++round) {
      team.run([&](int m) {
        std::size_t begin = 0, end = 0;
        WorkerTeam::chunk(hits.size(), m, team.size(), begin, end);
        for (std::size_t i = begin; i < end; ++i) {
          ++hits[i];
          if (owner[i] == -1) owner[i] = m;
          if (owner[i] != m) owner[i] = 99;  // another member touched it: partition not fixed
        }
      });
    }
    for (std::size_t i = 0; i < hits.size(); ++i) {
      ASSERT_EQ(hits[i], 200) << "size " << size << " index " << i;
      ASSERT_NE(owner[i], 99) << "size " << size << " index " << i;
    }
    std::vector<int> dealt(1001, -1);
    team.run([&](int m) {
      WorkerTeam::for_each_interleaved(dealt.size(), m, team.size(), 64, [&](std::size_t i) {
        dealt[i] = dealt[i] == -1 ? m : 99;  // 99: visited twice
      });
    });
    for (std::size_t i = 0; i < dealt.size(); ++i) {
      ASSERT_EQ(dealt[i], static_cast<int>((i / 64) % static_cast<std::size_t>(size))) << i;
    }
    EXPECT_EQ(team.jobs(), size == 1 ? 0u : 201u);
  }
  std::size_t b0 = 0, e0 = 0, b1 = 0, e1 = 0;
  WorkerTeam::chunk(1001, 0, 2, b0, e0);
  WorkerTeam::chunk(1001, 1, 2, b1, e1);
  EXPECT_EQ(b0, 0u);
  EXPECT_EQ(e0, b1);
  EXPECT_EQ(e1, 1001u);
}

TEST(WorkerTeam, ClaimedItemsRunExactlyOnceEachOnAValidMember) {
  for (int size : {1, 2, 3, 4}) {
    WorkerTeam team(size);
    for (std::size_t n : {std::size_t{0}, std::size_t{1}, std::size_t{7}, std::size_t{1001}}) {
      std::vector<std::atomic<int>> hits(n);
      std::atomic<int> bad_member{0};
      for (int round = 0; round < 50; ++round) {
        team.run_claimed(n, [&](int m, std::size_t i) {
          if (m < 0 || m >= team.size()) bad_member.fetch_add(1);
          hits[i].fetch_add(1, std::memory_order_relaxed);
        });
      }
      for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(hits[i].load(), 50) << size << " " << i;
      EXPECT_EQ(bad_member.load(), 0);
    }
  }
}

// A run_claimed() job waits only for the workers that joined it. Tiny jobs whose one item the
// caller claims at once close before a sleeping worker is up (late_workers counts those), every
// item still runs exactly once, and run() jobs in between still get every member. The caller
// checks the slots with plain reads: TSan flags them unless joining orders the writes.
TEST(WorkerTeam, ClaimedJobsCloseWithoutWorkersThatHaveNotJoined) {
  WorkerTeam team(3, ThreadSpec{.name = "late_w1"}, 0);
  const std::uint64_t jobs = test::stress_items(20'000);
  std::vector<std::uint64_t> slot(3 * 16, 0);
  std::uint64_t item_runs = 0, expect_each = 0;
  for (std::uint64_t j = 0; j < jobs; ++j) {
    team.run_claimed(1, [&](int m, std::size_t) {
      ++slot[static_cast<std::size_t>(m) * 16 + 1];
      ++item_runs;  // one item: never two members at once
    });
    ASSERT_EQ(item_runs, j + 1);
    if (j % 8 == 0) {
      team.run([&](int m) { ++slot[static_cast<std::size_t>(m) * 16]; });
      ++expect_each;
      for (int m = 0; m < 3; ++m) ASSERT_EQ(slot[static_cast<std::size_t>(m) * 16], expect_each);
    }
  }
  std::uint64_t by_members = 0;
  for (int m = 0; m < 3; ++m) by_members += slot[static_cast<std::size_t>(m) * 16 + 1];
  EXPECT_EQ(by_members, jobs);
  // On a loaded machine the caller itself may be held up while its jobs are open, so that every
  // worker joins in time; more empty jobs until one is late (a handful suffice unloaded).
  for (std::uint64_t extra = 0; team.late_workers() == 0 && extra < test::stress_items(200'000);
       ++extra)
    team.run_claimed(1, [](int, std::size_t) {});
  EXPECT_GT(team.late_workers(), 0u);
}

// The reason run_claimed exists: a member that is held up (preempted) on one item must not hold
// up the rest. The member that claims item 0 waits until every other item is done; a fixed
// partition would leave its share undone and time out.
TEST(WorkerTeam, AHeldUpMemberLeavesTheRestOfTheItemsToTheOthers) {
  WorkerTeam team(2);
  constexpr std::size_t kItems = 64;
  for (int round = 0; round < 20; ++round) {
    std::atomic<std::size_t> done{0};
    std::atomic<bool> timed_out{false};
    std::vector<int> member_of(kItems, -1);
    team.run_claimed(kItems, [&](int m, std::size_t i) {
      member_of[i] = m;
      if (i == 0) {
        const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
        while (done.load() < kItems - 1) {
          if (std::chrono::steady_clock::now() > deadline) {
            timed_out = true;
            break;
          }
          std::this_thread::yield();
        }
      }
      done.fetch_add(1);
    });
    ASSERT_FALSE(timed_out.load()) << "round " << round;
    for (std::size_t i = 1; i < kItems; ++i) EXPECT_NE(member_of[i], member_of[0]) << i;
  }
}

TEST(WorkerTeam, MemberZeroIsTheCallerAndWorkersCarryTheirSpecNames) {
  const ThreadSpec first{.name = "tracker_w1", .sched_fifo_priority = 0, .cpu = -1};
  WorkerTeam team(3, first);
  std::vector<std::thread::id> ids(3);
  std::vector<std::string> names(3);
  team.run([&](int m) {
    ids[static_cast<std::size_t>(m)] = std::this_thread::get_id();
    char buf[16] = {};
    pthread_getname_np(pthread_self(), buf, sizeof buf);
    names[static_cast<std::size_t>(m)] = buf;
  });
  EXPECT_EQ(ids[0], std::this_thread::get_id());
  EXPECT_NE(ids[1], ids[0]);
  EXPECT_NE(ids[2], ids[1]);
  EXPECT_EQ(names[1], "tracker_w1");
  EXPECT_EQ(names[2], "tracker_w2");
  EXPECT_EQ(team.worker(1).spec().name.view(), "tracker_w1");
  EXPECT_EQ(team.worker(2).spec().name.view(), "tracker_w2");
}

TEST(WorkerTeam, WorkerSpecKeepsPriorityAndPinsOnlyTheTableMember) {
  const ThreadSpec& w1 = thread_spec("tracker_w1");
  EXPECT_EQ(worker_spec(w1, 1).cpu, w1.cpu);
  const ThreadSpec w3 = worker_spec(w1, 3);
  EXPECT_EQ(w3.name.view(), "tracker_w3");
  EXPECT_EQ(w3.sched_fifo_priority, w1.sched_fifo_priority);
  EXPECT_EQ(w3.cpu, -1);
  EXPECT_EQ(worker_spec(thread_spec("mapper_w1"), 12).name.view(), "mapper_w12");
}

TEST(WorkerTeam, AnExceptionReachesTheCallerAfterEveryMemberFinished) {
  WorkerTeam team(3);
  std::atomic<int> finished{0};
  try {
    team.run([&](int m) {
      if (m == 2) throw std::runtime_error("member 2");
      if (m == 1) throw std::logic_error("member 1");
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      finished.fetch_add(1);
    });
    FAIL() << "no exception";
  } catch (const std::logic_error& e) {  // the lowest member index wins
    EXPECT_STREQ(e.what(), "member 1");
  }
  EXPECT_EQ(finished.load(), 1);
  EXPECT_THROW(team.run([](int m) {
    if (m == 0) throw std::out_of_range("caller");
  }),
               std::out_of_range);
  // The team is usable afterwards and the old errors are gone.
  std::atomic<int> ran{0};
  team.run([&](int) { ran.fetch_add(1); });
  EXPECT_EQ(ran.load(), 3);
}

// Many tiny jobs: each member adds to its own slot, the caller checks the slots after each run
// (a plain read: TSan flags it unless run() orders the workers' writes before its return).
void stress(std::int64_t spin_ns, std::uint64_t jobs) {
  WorkerTeam team(2, ThreadSpec{.name = "stress_w1"}, spin_ns);
  std::vector<std::uint64_t> slot(2 * 16, 0);  // 16 apart: no false sharing
  for (std::uint64_t j = 0; j < jobs; ++j) {
    team.run([&](int m) { slot[static_cast<std::size_t>(m) * 16] += j; });
    const std::uint64_t expect = j * (j + 1) / 2;
    ASSERT_EQ(slot[0], expect) << j;
    ASSERT_EQ(slot[16], expect) << j;
  }
  EXPECT_EQ(team.jobs(), jobs);
}

TEST(WorkerTeam, TwoThreadStressWithSpinThenFutex) {
  stress(WorkerTeam::kRealtimeSpinNs, test::stress_items(20'000));
}

TEST(WorkerTeam, SpinsOnlyWhenTheWorkersAreRealTime) {
  EXPECT_EQ(WorkerTeam(2).spin_ns(), 0);  // SCHED_OTHER workers: futex only
  EXPECT_EQ(WorkerTeam(2, ThreadSpec{.name = "spin_w1"}, 1234).spin_ns(), 1234);
  EXPECT_EQ(WorkerTeam(1).spin_ns(), 0);
}

TEST(WorkerTeam, TwoThreadStressFutexOnly) {
  // spin 0: every wait goes to the futex, the path the spin hides on an idle machine.
  WorkerTeam probe(2, ThreadSpec{.name = "probe_w1"}, 0);
  for (int i = 0; i < 100; ++i) {
    probe.run([](int) {});
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  EXPECT_GT(probe.worker_sleeps(), 0u);
  stress(0, test::stress_items(100'000));
}

TEST(WorkerTeam, IdleWorkersSleepAndAreJoinedPromptly) {
  using Clock = std::chrono::steady_clock;
  Clock::time_point join_t0;
  {
    WorkerTeam team(4);
    team.run([](int) {});
    // The workers go to FUTEX_WAIT (no spin for SCHED_OTHER teams) as soon as they are
    // scheduled; on a loaded machine that may take a while (2.6 s once under ctest -j2 beside
    // the real-time tests), so the wait has a generous deadline and the promptness measured is
    // the join's alone.
    const auto deadline = Clock::now() + std::chrono::seconds(30);
    while (team.worker_sleeps() < 3u && Clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    EXPECT_GE(team.worker_sleeps(), 3u);
    join_t0 = Clock::now();
  }
  EXPECT_LT(Clock::now() - join_t0, std::chrono::seconds(5));
}

TEST(WorkerTeam, SizeIsClamped) {
  EXPECT_EQ(WorkerTeam(0).size(), 1);
  EXPECT_EQ(WorkerTeam(-3).size(), 1);
  int calls = 0;
  WorkerTeam one(1);
  one.run([&](int m) {
    EXPECT_EQ(m, 0);
    ++calls;
  });
  EXPECT_EQ(calls, 1);
}

}  // namespace
}  // namespace vigs::rt
