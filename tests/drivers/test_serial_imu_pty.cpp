// The real SerialImuDriver reading the slave of a pseudo-terminal while a feeder thread writes
// recorded IMU bytes (EuRoC samples encoded as Xsens MTData2) to the master, paced by time.
#include <gtest/gtest.h>

#include <termios.h>

#include <unistd.h>

#include <chrono>
#include <system_error>
#include <thread>

#include "../common/temp_files.hpp"
#include "drivers/serial_imu/serial_imu_driver.hpp"
#include "drivers/serial_imu/serial_port.hpp"
#include "pty_feeder.hpp"
#include "rt/clock.hpp"

namespace vigs::drivers {
namespace {

using test::TestSample;

SerialImuDriverSettings settings_for(const test::Pty& pty) {
  SerialImuDriverSettings s;
  s.port = pty.slave_path();
  s.baud = 921600;
  s.realtime_thread = false;  // tests run unprivileged on a shared machine
  s.pin_cpu = false;
  return s;
}

// Waits (up to 10 s) until `done()`; returns whether it happened.
template <class F>
bool wait_for(F done) {
  const std::int64_t deadline = rt::monotonic_ns() + rt::s_to_ns(std::int64_t{10});
  while (!done()) {
    if (rt::monotonic_ns() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

std::vector<ImuSample> drain(rt::SpscRing<ImuSample>& ring) {
  std::vector<ImuSample> out;
  ImuSample s;
  while (ring.try_pop(s)) out.push_back(s);
  return out;
}

void expect_values(const ImuSample& got, const TestSample& want) {
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(got.accel_mps2[i], want.accel_mps2[i]);
    EXPECT_EQ(got.gyro_rps[i], want.gyro_rps[i]);
  }
}

// Stops the driver, checking that it does not stall (a liveness bound, not a speed goal).
void stop_promptly(SerialImuDriver& driver) {
  const std::int64_t t = rt::monotonic_ns();
  driver.stop();
  EXPECT_LT(rt::monotonic_ns() - t, rt::s_to_ns(std::int64_t{2}));
  EXPECT_FALSE(driver.running());
}

TEST(SerialImuPty, CleanDataArrivesComplete) {
  test::Pty pty;
  rt::SpscRing<ImuSample> ring(1024);
  SerialImuDriver driver(settings_for(pty), ring);
  driver.start();
  const auto samples = test::euroc_samples(300, 123'456);
  std::size_t total = 0;
  for (const auto& seg : test::clean_segments(samples)) total += seg.bytes.size();
  test::PacedFeeder feeder(pty, test::clean_segments(samples));
  feeder.join();
  ASSERT_TRUE(wait_for([&] { return driver.faults().samples_out >= samples.size() - 64; }));
  ASSERT_TRUE(wait_for([&] { return driver.faults().bytes_read == total; }));
  stop_promptly(driver);  // releases samples still held for the clock fit's warm-up
  const std::int64_t stopped_ns = rt::monotonic_ns();

  const auto out = drain(ring);
  ASSERT_EQ(out.size(), samples.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    expect_values(out[i], samples[i]);
    if (i > 0) {
      EXPECT_GT(out[i].t_ns, out[i - 1].t_ns) << i;
    }
    EXPECT_GT(out[i].t_ns, feeder.start_ns() - rt::ms_to_ns(50));
    EXPECT_LT(out[i].t_ns, stopped_ns);
  }
  const SerialImuFaults f = driver.faults();
  EXPECT_EQ(f.packets_ok, samples.size());
  EXPECT_EQ(f.samples_out, samples.size());
  EXPECT_EQ(f.bad_checksum + f.resync_bytes_skipped + f.oversize_length + f.sample_counter_gap +
                f.non_monotonic_stamp + f.ring_drops + f.malformed_payload + f.incomplete_sample +
                f.read_errors + f.truncated_at_hangup,
            0u)
      << f.to_string();
}

TEST(SerialImuPty, FaultyCutOffStreamYieldsExactlyTheGoodPackets) {
  const auto samples = test::euroc_samples(300, 0xFFFFFFFFu - 50 * 100);  // wraps mid-stream
  test::FaultyStreamBuilder b(9);
  for (std::size_t i = 0; i + 2 < samples.size(); ++i) {
    switch (i % 11) {
      case 2:
        b.garbage(5 + i % 60, samples[i].sample_time_fine);
        b.good(samples[i]);
        break;
      case 4:
        b.flipped(samples[i]);
        break;
      case 6:
        b.truncated(samples[i], 4 + i % 35);
        break;
      case 8:
        b.oversize_header(samples[i].sample_time_fine);
        b.good(samples[i]);
        break;
      case 9:  // two lost in a row: one gap of two samples
        b.flipped(samples[i]);
        b.truncated(samples[i + 1], 10);
        ++i;
        break;
      default:
        b.good(samples[i]);
    }
  }
  b.good(samples[samples.size() - 2]);
  b.cut_off(samples.back(), 17);
  const auto want = b.finish();
  const std::size_t total = b.bytes().size();

  test::Pty pty;
  rt::SpscRing<ImuSample> ring(1024);
  SerialImuDriver driver(settings_for(pty), ring);
  driver.start();
  test::PacedFeeder feeder(pty, b.segments(), [&] { return driver.faults().bytes_read == total; });
  feeder.join();
  ASSERT_EQ(feeder.bytes_written(), total);
  ASSERT_TRUE(wait_for([&] { return driver.faults().hangups >= 1; }));
  const SerialImuFaults f = driver.faults();  // complete once the hang-up was seen
  stop_promptly(driver);

  const auto out = drain(ring);
  ASSERT_EQ(out.size(), b.survivors().size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    expect_values(out[i], b.survivors()[i]);
    if (i > 0) {
      EXPECT_GT(out[i].t_ns, out[i - 1].t_ns) << i;
    }
  }
  EXPECT_EQ(f.bytes_read, total);
  EXPECT_EQ(f.packets_ok, want.packets_ok);
  EXPECT_EQ(f.samples_out, want.packets_ok);
  EXPECT_EQ(f.bad_checksum, want.bad_checksum);
  EXPECT_EQ(f.resync_bytes_skipped, want.resync_bytes_skipped);
  EXPECT_EQ(f.oversize_length, want.oversize_length);
  EXPECT_EQ(f.sample_counter_gap, want.sample_counter_gap);
  EXPECT_EQ(f.samples_missed, want.samples_missed);
  EXPECT_EQ(f.truncated_at_hangup, 1u);
  EXPECT_EQ(f.hangups, 1u);
  EXPECT_EQ(f.non_monotonic_stamp + f.ring_drops + f.read_errors + f.malformed_payload, 0u)
      << f.to_string();
  EXPECT_GT(want.bad_checksum, 30u);
  EXPECT_GT(want.sample_counter_gap, 30u);
}

TEST(SerialImuPty, FullRingDropsTheNewestAndCounts) {
  test::Pty pty;
  rt::SpscRing<ImuSample> ring(16);  // nobody pops
  auto settings = settings_for(pty);
  settings.stamper.warmup_samples = 0;
  SerialImuDriver driver(settings, ring);
  driver.start();
  const auto samples = test::euroc_samples(100, 0);
  test::PacedFeeder feeder(pty, test::clean_segments(samples));
  feeder.join();
  ASSERT_TRUE(wait_for([&] { return driver.faults().samples_out == samples.size(); }));
  stop_promptly(driver);
  EXPECT_EQ(driver.faults().ring_drops, samples.size() - 16);
  const auto out = drain(ring);
  ASSERT_EQ(out.size(), 16u);
  for (std::size_t i = 0; i < out.size(); ++i) expect_values(out[i], samples[i]);  // oldest kept
}

TEST(SerialImuPty, RestartTakesANewDeviceTimeBase) {
  test::Pty pty;
  rt::SpscRing<ImuSample> ring(1024);
  SerialImuDriver driver(settings_for(pty), ring);
  const auto first = test::euroc_samples(100, 4'000'000);
  const auto second = test::euroc_samples(100, 0);  // the device restarted its counter
  for (const auto* run : {&first, &second}) {
    driver.start();
    test::PacedFeeder feeder(pty, test::clean_segments(*run));
    feeder.join();
    const std::uint64_t want = (run == &first ? 1 : 2) * run->size();
    ASSERT_TRUE(wait_for([&] { return driver.faults().packets_ok == want; }));
    stop_promptly(driver);
  }
  const auto out = drain(ring);
  ASSERT_EQ(out.size(), first.size() + second.size());
  for (std::size_t i = 1; i < out.size(); ++i) EXPECT_GT(out[i].t_ns, out[i - 1].t_ns) << i;
  const SerialImuFaults f = driver.faults();
  EXPECT_EQ(f.non_monotonic_stamp + f.clock_resets + f.sample_counter_gap, 0u) << f.to_string();
}

TEST(SerialImuPty, ReopensWhenTheDeviceComesBackUnderItsName) {
  // A USB adapter unplugged and plugged in again: its udev name (here a symlink) now points to a
  // new tty. The driver reopens the path and carries on with a new device time base.
  vigs::test::TempFiles files("imu_link");  // the symlink goes however the test ends
  const std::string link = files.path("tty");
  ::unlink(link.c_str());
  test::Pty first;
  ASSERT_EQ(::symlink(first.slave_path().c_str(), link.c_str()), 0);
  rt::SpscRing<ImuSample> ring(1024);
  SerialImuDriverSettings s = settings_for(first);
  s.port = link;
  s.reopen_interval_ms = 50;
  SerialImuDriver driver(s, ring);
  driver.start();
  const auto a = test::euroc_samples(100, 9'000);
  const auto b = test::euroc_samples(100, 0);
  std::size_t a_bytes = 0;
  for (const auto& seg : test::clean_segments(a)) a_bytes += seg.bytes.size();
  {
    // Unplug: the name disappears first (pty numbers are reused at once, so another process's
    // new pty could otherwise take the old name), then the line hangs up.
    test::PacedFeeder feeder(first, test::clean_segments(a), [&] {
      if (driver.faults().bytes_read != a_bytes) return false;
      const std::string dangling = link + ".unplugged";
      return ::symlink("/nonexistent/ttyIMU", dangling.c_str()) == 0 &&
             ::rename(dangling.c_str(), link.c_str()) == 0;
    });
  }
  ASSERT_TRUE(wait_for([&] { return driver.faults().hangups == 1; }));
  test::Pty second;  // the device is back, under a new tty
  const std::string tmp_link = link + ".new";
  ASSERT_EQ(::symlink(second.slave_path().c_str(), tmp_link.c_str()), 0);
  ASSERT_EQ(::rename(tmp_link.c_str(), link.c_str()), 0);
  ASSERT_TRUE(wait_for([&] { return driver.faults().reopens == 1; }));
  { test::PacedFeeder feeder(second, test::clean_segments(b)); }
  ASSERT_TRUE(wait_for([&] { return driver.faults().packets_ok == a.size() + b.size(); }));
  stop_promptly(driver);
  ::unlink(link.c_str());

  const auto out = drain(ring);
  ASSERT_EQ(out.size(), a.size() + b.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    expect_values(out[i], i < a.size() ? a[i] : b[i - a.size()]);
    if (i > 0) {
      EXPECT_GT(out[i].t_ns, out[i - 1].t_ns) << i;
    }
  }
  const SerialImuFaults f = driver.faults();
  EXPECT_EQ(f.hangups, 1u);
  EXPECT_EQ(f.reopens, 1u);
  EXPECT_EQ(f.non_monotonic_stamp + f.clock_resets + f.sample_counter_gap + f.bad_checksum, 0u)
      << f.to_string();
}

TEST(SerialImuPty, StopsPromptlyWithoutData) {
  test::Pty pty;
  rt::SpscRing<ImuSample> ring(16);
  SerialImuDriver driver(settings_for(pty), ring);
  driver.start();
  EXPECT_TRUE(driver.running());
  std::this_thread::sleep_for(std::chrono::milliseconds(60));
  stop_promptly(driver);
  driver.stop();  // idempotent
  EXPECT_EQ(driver.faults().bytes_read, 0u);
}

TEST(SerialPort, StandardAndCustomBaudRates) {
  test::Pty pty;
  {
    SerialPort port = SerialPort::open(pty.slave_path(), 921600);
    termios tio{};
    ASSERT_EQ(::tcgetattr(port.fd(), &tio), 0);
    EXPECT_EQ(::cfgetospeed(&tio), static_cast<speed_t>(B921600));
    EXPECT_EQ(read_termios2_baud(port.fd()), 921600);
    EXPECT_EQ(tio.c_lflag & (ICANON | ECHO | ISIG), 0u);  // raw
  }
  for (int baud : {250000, 1000000, 2000000, 3125000}) {
    SerialPort port = SerialPort::open(pty.slave_path(), baud);
    EXPECT_EQ(read_termios2_baud(port.fd()), baud);
  }
  EXPECT_EQ(standard_baud_constant(115200), static_cast<unsigned>(B115200));
  EXPECT_EQ(standard_baud_constant(250000), 0u);
}

TEST(SerialPort, ErrorsNameThePortAndTheStep) {
  try {
    (void)SerialPort::open("/nonexistent/ttyIMU", 921600);
    FAIL();
  } catch (const std::system_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/ttyIMU"), std::string::npos) << e.what();
  }
  try {
    (void)SerialPort::open("/dev/null", 921600);
    FAIL();
  } catch (const std::system_error& e) {
    EXPECT_NE(std::string(e.what()).find("tcgetattr"), std::string::npos) << e.what();
  }
  rt::SpscRing<ImuSample> ring(16);
  SerialImuDriverSettings s;
  s.port = "/nonexistent/ttyIMU";
  SerialImuDriver driver(s, ring);
  EXPECT_THROW(driver.start(), std::system_error);
  EXPECT_FALSE(driver.running());
}

TEST(SerialImuFaults, JsonAndTextNameEveryCounter) {
  SerialImuFaults f;
  f.bad_checksum = 3;
  f.ring_drops = 7;
  const std::string j = f.to_json();
  EXPECT_EQ(j.front(), '{');
  EXPECT_EQ(j.back(), '}');
  EXPECT_NE(j.find("\"bad_checksum\": 3"), std::string::npos);
  EXPECT_NE(j.find("\"ring_drops\": 7"), std::string::npos);
  for (const char* k : {"resync_bytes_skipped", "oversize_length", "sample_counter_gap",
                        "non_monotonic_stamp", "packets_ok"}) {
    EXPECT_NE(j.find(k), std::string::npos) << k;
  }
  EXPECT_NE(f.to_string().find("bad_checksum=3"), std::string::npos);
}

}  // namespace
}  // namespace vigs::drivers
