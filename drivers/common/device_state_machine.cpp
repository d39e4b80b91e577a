#include "drivers/common/device_state_machine.hpp"

#include <algorithm>
#include <stdexcept>

namespace vigs::drivers {

std::string_view to_string(DeviceState s) noexcept {
  switch (s) {
    case DeviceState::kOpening:
      return "opening";
    case DeviceState::kStreaming:
      return "streaming";
    case DeviceState::kLost:
      return "lost";
    case DeviceState::kEnded:
      return "ended";
    case DeviceState::kFailed:
      return "failed";
  }
  return "?";
}

std::string_view to_string(DeviceFault f) noexcept {
  switch (f) {
    case DeviceFault::kNone:
      return "none";
    case DeviceFault::kOpenFailed:
      return "open failed";
    case DeviceFault::kFrameTimeout:
      return "frame timeout";
    case DeviceFault::kReadErrors:
      return "read errors";
    case DeviceFault::kDeviceGone:
      return "device gone";
  }
  return "?";
}

DeviceStateMachine::DeviceStateMachine(const DeviceStateSettings& settings) : settings_(settings) {
  if (settings.frame_timeout_ns <= 0 || settings.backoff_initial_ns <= 0 ||
      settings.backoff_max_ns < settings.backoff_initial_ns ||
      settings.max_consecutive_errors == 0) {
    throw std::invalid_argument(
        "DeviceStateMachine: frame_timeout_ns and backoff_initial_ns must be > 0, backoff_max_ns "
        ">= backoff_initial_ns, max_consecutive_errors >= 1");
  }
  reset(0);
}

void DeviceStateMachine::reset(std::int64_t now_ns) noexcept {
  state_ = DeviceState::kOpening;
  fault_ = DeviceFault::kNone;
  next_open_ns_ = now_ns;
  last_frame_ns_ = now_ns;
  backoff_ns_ = settings_.backoff_initial_ns;
  consecutive_errors_ = 0;
  consecutive_open_failures_ = 0;
  for (rt::SingleWriterCounter* c : {&opens_, &open_failures_, &losses_, &frame_timeouts_,
                                     &error_resets_, &device_gone_, &read_errors_}) {
    c->reset();
  }
}

void DeviceStateMachine::on_open_ok(std::int64_t now_ns) noexcept {
  if (state_ != DeviceState::kOpening) return;
  opens_.add();
  state_ = DeviceState::kStreaming;
  last_frame_ns_ = now_ns;  // the frame timeout runs from the open
  consecutive_errors_ = 0;
  consecutive_open_failures_ = 0;
  backoff_ns_ = settings_.backoff_initial_ns;
}

void DeviceStateMachine::on_open_failed(std::int64_t now_ns) noexcept {
  if (state_ != DeviceState::kOpening) return;
  open_failures_.add();
  ++consecutive_open_failures_;
  if (!settings_.reopen || (settings_.max_open_attempts != 0 &&
                            consecutive_open_failures_ >= settings_.max_open_attempts)) {
    fault_ = DeviceFault::kOpenFailed;
    state_ = DeviceState::kFailed;
    return;
  }
  next_open_ns_ = now_ns + backoff_ns_;
  backoff_ns_ = std::min(backoff_ns_ * 2, settings_.backoff_max_ns);
}

void DeviceStateMachine::on_frame(std::int64_t now_ns) noexcept {
  if (state_ != DeviceState::kStreaming) return;
  last_frame_ns_ = now_ns;
  consecutive_errors_ = 0;
}

void DeviceStateMachine::on_read_error(std::int64_t now_ns) noexcept {
  if (state_ != DeviceState::kStreaming) return;
  read_errors_.add();
  if (++consecutive_errors_ >= settings_.max_consecutive_errors) {
    lose(DeviceFault::kReadErrors, now_ns);
  }
}

void DeviceStateMachine::on_device_gone(std::int64_t now_ns) noexcept {
  if (state_ == DeviceState::kStreaming) lose(DeviceFault::kDeviceGone, now_ns);
}

void DeviceStateMachine::on_end_of_stream() noexcept {
  if (state_ == DeviceState::kStreaming) state_ = DeviceState::kEnded;
}

bool DeviceStateMachine::check_timeout(std::int64_t now_ns) noexcept {
  if (state_ != DeviceState::kStreaming || now_ns - last_frame_ns_ < settings_.frame_timeout_ns) {
    return false;
  }
  lose(DeviceFault::kFrameTimeout, now_ns);
  return true;
}

void DeviceStateMachine::on_closed(std::int64_t now_ns) noexcept {
  if (state_ != DeviceState::kLost) return;
  if (!settings_.reopen) {
    state_ = DeviceState::kFailed;  // fault_ keeps why it was lost
    return;
  }
  state_ = DeviceState::kOpening;
  next_open_ns_ = now_ns + backoff_ns_;
  backoff_ns_ = std::min(backoff_ns_ * 2, settings_.backoff_max_ns);
}

void DeviceStateMachine::lose(DeviceFault why, std::int64_t now_ns) noexcept {
  (void)now_ns;
  fault_ = why;
  state_ = DeviceState::kLost;
  losses_.add();
  (why == DeviceFault::kFrameTimeout ? frame_timeouts_
   : why == DeviceFault::kReadErrors ? error_resets_
                                     : device_gone_)
      .add();
  consecutive_errors_ = 0;
}

std::int64_t DeviceStateMachine::deadline_ns() const noexcept {
  switch (state_) {
    case DeviceState::kOpening:
      return next_open_ns_;
    case DeviceState::kStreaming:
      return last_frame_ns_ + settings_.frame_timeout_ns;
    default:
      return 0;
  }
}

DeviceStateCounters DeviceStateMachine::counters() const noexcept {
  return {.opens = opens_.get(),
          .open_failures = open_failures_.get(),
          .losses = losses_.get(),
          .frame_timeouts = frame_timeouts_.get(),
          .error_resets = error_resets_.get(),
          .device_gone = device_gone_.get(),
          .read_errors = read_errors_.get()};
}

}  // namespace vigs::drivers
