// PseudoTerminal: a pty pair standing in for a serial device. The master side is written by a
// feeder (`vigs imu play`, `vigs run --through-drivers`, the driver tests); the real serial driver
// opens slave_path() as it would /dev/ttyUSB0. A pty does not pace by baud rate: the feeder
// paces itself by the samples' stamps.
// The slave is held open (raw mode) for the pair's lifetime, so its line settings persist
// between the driver's opens. Closing the master is a hang-up for the reader, and it discards
// whatever the slave has not read yet.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace vigs::drivers {

class PseudoTerminal {
 public:
  /// posix_openpt, grantpt, unlockpt; the slave opened and set raw. Throws std::system_error
  /// naming the failing step.
  PseudoTerminal();
  ~PseudoTerminal();
  PseudoTerminal(const PseudoTerminal&) = delete;
  PseudoTerminal& operator=(const PseudoTerminal&) = delete;

  [[nodiscard]] const std::string& slave_path() const noexcept { return slave_path_; }
  [[nodiscard]] int master_fd() const noexcept { return master_; }
  /// Writes every byte to the master (retrying on EINTR and short writes). False when the
  /// master is closed or write() fails (errno says why).
  [[nodiscard]] bool write_all(std::span<const std::uint8_t> bytes) const noexcept;
  /// Hangs up the reader. Idempotent.
  void close_master() noexcept;

 private:
  int master_ = -1;
  int slave_ = -1;
  std::string slave_path_;
};

}  // namespace vigs::drivers
