// The camera drivers' life cycle (drivers/common/device_state_machine.hpp) on a scripted clock:
// open, stream, lost (frame timeout, a run of read errors, device gone), reopen with a doubling
// backoff, end of a recording, and the final failed state when reopening is off or exhausted.
#include "drivers/common/device_state_machine.hpp"

#include <gtest/gtest.h>

namespace vigs::drivers {
namespace {

constexpr std::int64_t kMs = 1'000'000;

DeviceStateSettings settings() {
  return {.frame_timeout_ns = 500 * kMs,
          .max_consecutive_errors = 3,
          .backoff_initial_ns = 100 * kMs,
          .backoff_max_ns = 400 * kMs,
          .reopen = true,
          .max_open_attempts = 0};
}

TEST(DeviceStateMachine, OpensAtOnceThenStreamsWhileFramesArrive) {
  DeviceStateMachine m(settings());
  EXPECT_EQ(m.state(), DeviceState::kOpening);
  EXPECT_TRUE(m.due_to_open(0));
  m.on_open_ok(0);
  EXPECT_EQ(m.state(), DeviceState::kStreaming);
  EXPECT_EQ(m.deadline_ns(), 500 * kMs);
  for (std::int64_t t = 0; t <= 5000 * kMs; t += 400 * kMs) {
    m.on_frame(t);
    EXPECT_FALSE(m.check_timeout(t + 499 * kMs));
  }
  EXPECT_EQ(m.state(), DeviceState::kStreaming);
  EXPECT_EQ(m.counters().opens, 1u);
  EXPECT_EQ(m.counters().losses, 0u);
}

TEST(DeviceStateMachine, FrameTimeoutLosesTheStreamAndReopensAfterADoublingBackoff) {
  DeviceStateMachine m(settings());
  m.on_open_ok(0);
  m.on_frame(100 * kMs);
  EXPECT_FALSE(m.check_timeout(599 * kMs));
  EXPECT_TRUE(m.check_timeout(600 * kMs));
  EXPECT_EQ(m.state(), DeviceState::kLost);
  EXPECT_EQ(m.last_fault(), DeviceFault::kFrameTimeout);
  m.on_closed(600 * kMs);
  EXPECT_EQ(m.state(), DeviceState::kOpening);
  // First wait 100 ms, then 200, 400, and 400 again (the maximum).
  std::int64_t t = 600 * kMs;
  for (const std::int64_t wait_ms : {100, 200, 400, 400}) {
    EXPECT_FALSE(m.due_to_open(t + wait_ms * kMs - 1));
    EXPECT_EQ(m.deadline_ns(), t + wait_ms * kMs);
    t += wait_ms * kMs;
    ASSERT_TRUE(m.due_to_open(t));
    if (wait_ms == 400 && t > 1500 * kMs) break;
    m.on_open_failed(t);
  }
  m.on_open_ok(t);
  EXPECT_EQ(m.state(), DeviceState::kStreaming);
  EXPECT_EQ(m.backoff_ns(), 100 * kMs);  // a good open starts the backoff over
  const DeviceStateCounters c = m.counters();
  EXPECT_EQ(c.opens, 2u);
  EXPECT_EQ(c.open_failures, 3u);
  EXPECT_EQ(c.losses, 1u);
  EXPECT_EQ(c.frame_timeouts, 1u);
  // The frame timeout runs from the reopen, not from the last frame before the loss.
  EXPECT_FALSE(m.check_timeout(t + 499 * kMs));
}

TEST(DeviceStateMachine, ARunOfReadErrorsForcesAResetAndAFrameClearsTheCount) {
  DeviceStateMachine m(settings());
  m.on_open_ok(0);
  m.on_read_error(1);
  m.on_read_error(2);
  m.on_frame(3);  // clears the run
  m.on_read_error(4);
  m.on_read_error(5);
  EXPECT_EQ(m.state(), DeviceState::kStreaming);
  m.on_read_error(6);
  EXPECT_EQ(m.state(), DeviceState::kLost);
  EXPECT_EQ(m.last_fault(), DeviceFault::kReadErrors);
  const DeviceStateCounters c = m.counters();
  EXPECT_EQ(c.read_errors, 5u);
  EXPECT_EQ(c.error_resets, 1u);
  EXPECT_EQ(c.losses, 1u);
}

TEST(DeviceStateMachine, DeviceGoneIsCountedApartAndReopened) {
  DeviceStateMachine m(settings());
  m.on_open_ok(0);
  m.on_device_gone(10 * kMs);
  EXPECT_EQ(m.state(), DeviceState::kLost);
  EXPECT_EQ(m.last_fault(), DeviceFault::kDeviceGone);
  m.on_closed(10 * kMs);
  EXPECT_TRUE(m.due_to_open(110 * kMs));
  m.on_open_ok(110 * kMs);
  const DeviceStateCounters c = m.counters();
  EXPECT_EQ(c.device_gone, 1u);
  EXPECT_EQ(c.frame_timeouts + c.error_resets, 0u);
  EXPECT_EQ(c.opens, 2u);
}

TEST(DeviceStateMachine, WithoutReopenALossOrAFailedOpenIsFinal) {
  DeviceStateSettings s = settings();
  s.reopen = false;
  DeviceStateMachine m(s);
  m.on_open_ok(0);
  EXPECT_TRUE(m.check_timeout(500 * kMs));
  m.on_closed(500 * kMs);
  EXPECT_EQ(m.state(), DeviceState::kFailed);
  EXPECT_TRUE(m.final());
  EXPECT_EQ(m.last_fault(), DeviceFault::kFrameTimeout);
  m.on_open_ok(600 * kMs);  // ignored: final
  EXPECT_EQ(m.state(), DeviceState::kFailed);

  m.reset(0);
  EXPECT_EQ(m.counters().losses, 0u);
  m.on_open_failed(0);
  EXPECT_EQ(m.state(), DeviceState::kFailed);
  EXPECT_EQ(m.last_fault(), DeviceFault::kOpenFailed);
}

TEST(DeviceStateMachine, MaxOpenAttemptsEndsInFailed) {
  DeviceStateSettings s = settings();
  s.max_open_attempts = 3;
  DeviceStateMachine m(s);
  std::int64_t t = 0;
  for (int i = 0; i < 2; ++i) {
    m.on_open_failed(t);
    EXPECT_EQ(m.state(), DeviceState::kOpening);
    t = m.deadline_ns();
  }
  m.on_open_failed(t);
  EXPECT_EQ(m.state(), DeviceState::kFailed);
  EXPECT_EQ(m.counters().open_failures, 3u);
}

TEST(DeviceStateMachine, EndOfARecordingIsFinalWithoutAFault) {
  DeviceStateMachine m(settings());
  m.on_open_ok(0);
  m.on_end_of_stream();
  EXPECT_EQ(m.state(), DeviceState::kEnded);
  EXPECT_EQ(m.last_fault(), DeviceFault::kNone);
  EXPECT_FALSE(m.check_timeout(10'000 * kMs));
  EXPECT_TRUE(m.final());
}

TEST(DeviceStateMachine, InvalidSettingsAreRejected) {
  DeviceStateSettings s = settings();
  s.frame_timeout_ns = 0;
  EXPECT_THROW(DeviceStateMachine{s}, std::invalid_argument);
  s = settings();
  s.backoff_max_ns = s.backoff_initial_ns - 1;
  EXPECT_THROW(DeviceStateMachine{s}, std::invalid_argument);
}

}  // namespace
}  // namespace vigs::drivers
