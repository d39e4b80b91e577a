#pragma once
// Test support: a pipe(2) standing in for a GPIO line's event fd (the GPIO trigger's seam): a
// test writes kernel lineevent records into `w`, the driver reads `r`. Closed on destruction.
#include <fcntl.h>
#include <linux/gpio.h>
#include <unistd.h>

#include <cstdint>

namespace vigs::test {

struct GpioEventPipe {
  int r = -1, w = -1;
  GpioEventPipe() {
    int fds[2];
    if (::pipe2(fds, O_CLOEXEC) == 0) {
      r = fds[0];
      w = fds[1];
    }
  }
  ~GpioEventPipe() {
    if (r >= 0) ::close(r);
    if (w >= 0) ::close(w);
  }
  GpioEventPipe(const GpioEventPipe&) = delete;
  GpioEventPipe& operator=(const GpioEventPipe&) = delete;
  /// One event exactly as the kernel's lineevent read() returns it; false unless all of it was
  /// written.
  [[nodiscard]] bool write_edge(std::int64_t t_ns,
                                std::uint32_t id = GPIOEVENT_EVENT_RISING_EDGE) const {
    gpioevent_data e{};
    e.timestamp = static_cast<__u64>(t_ns);
    e.id = id;
    return ::write(w, &e, sizeof e) == static_cast<ssize_t>(sizeof e);
  }
};

}  // namespace vigs::test
