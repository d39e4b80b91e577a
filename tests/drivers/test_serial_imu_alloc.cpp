// The driver's read loop does not allocate: this binary replaces global operator new
// (counting_new.hpp) and counts allocations made by the thread named `imu_driver` (the rt thread
// table's name for the driver thread) while it reads clean and faulty streams through a pty,
// overflows its ring, hangs up, tries to reopen the vanished port, and stops.
#include <gtest/gtest.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <string>

#include "../common/counting_new.hpp"
#include "../common/temp_files.hpp"
#include "drivers/serial_imu/serial_imu_driver.hpp"
#include "pty_feeder.hpp"
#include "rt/clock.hpp"

namespace {

std::atomic<long> g_driver_thread_allocations{0};

}  // namespace

void vigs::test::on_operator_new(std::size_t, void*) noexcept {
  if (on_thread_named("imu_driver")) g_driver_thread_allocations.fetch_add(1);
}

namespace vigs::drivers {
namespace {

TEST(SerialImuDriver, ReadLoopDoesNotAllocate) {
  const auto samples = test::euroc_samples(150, 7);
  test::FaultyStreamBuilder b(5);
  for (std::size_t i = 0; i + 2 < samples.size(); ++i) {
    if (i % 7 == 3) b.flipped(samples[i]);
    if (i % 7 == 5) b.garbage(9, samples[i].sample_time_fine);
    if (i % 7 == 6) b.truncated(samples[i], 12);
    if (i % 7 != 3 && i % 7 != 6) b.good(samples[i]);
  }
  b.good(samples[samples.size() - 2]);
  b.cut_off(samples.back(), 11);
  (void)b.finish();
  const std::size_t total = b.bytes().size();

  test::Pty pty;
  // Through a symlink (a /dev/pts path is never reopened), moved to a dangling target before the
  // hang-up so that reopen attempts fail instead of finding a reused pty number.
  vigs::test::TempFiles files("imu_alloc");  // the symlink goes however the test ends
  const std::string link = files.path("tty");
  ::unlink(link.c_str());
  ASSERT_EQ(::symlink(pty.slave_path().c_str(), link.c_str()), 0);
  rt::SpscRing<ImuSample> ring(16);  // small: the drop path runs too
  SerialImuDriverSettings s;
  s.port = link;
  s.realtime_thread = false;
  s.pin_cpu = false;
  s.reopen_interval_ms = 10;  // reopen attempts (the pty is gone: they fail) run before stop
  SerialImuDriver driver(s, ring);
  driver.start();
  ASSERT_NE(driver.thread_status(), nullptr);
  ASSERT_EQ(driver.thread_status()->name, rt::ApplyResult::kApplied);  // named imu_driver
  {
    test::PacedFeeder feeder(pty, b.segments(), [&] {
      if (driver.faults().bytes_read != total) return false;
      const std::string dangling = link + ".unplugged";
      return ::symlink("/nonexistent/ttyIMU", dangling.c_str()) == 0 &&
             ::rename(dangling.c_str(), link.c_str()) == 0;
    });
  }
  const std::int64_t deadline = rt::monotonic_ns() + rt::s_to_ns(std::int64_t{10});
  while (driver.faults().hangups == 0 && rt::monotonic_ns() < deadline) {
    rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(5));
  }
  rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(100));
  driver.stop();
  ::unlink(link.c_str());
  const SerialImuFaults f = driver.faults();
  ASSERT_EQ(f.hangups, 1u);
  EXPECT_GT(f.packets_ok, 100u);
  EXPECT_GT(f.bad_checksum, 10u);
  EXPECT_GT(f.ring_drops, 0u);
  EXPECT_EQ(g_driver_thread_allocations.load(), 0);
}

TEST(SerialImuDriver, AllocationCounterSeesTheDriverThread) {
  // The check above could pass vacuously if the name test never matched: prove it matches.
  ::prctl(PR_SET_NAME, "imu_driver", 0, 0, 0);
  const long before = g_driver_thread_allocations.load();
  // A direct call: a new-expression paired with delete may be elided by the optimiser.
  void* p = ::operator new(sizeof(int));
  ::operator delete(p);
  ::prctl(PR_SET_NAME, "test_main", 0, 0, 0);
  EXPECT_EQ(g_driver_thread_allocations.load(), before + 1);
}

}  // namespace
}  // namespace vigs::drivers
