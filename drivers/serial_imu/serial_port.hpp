// SerialPort: a serial device opened in termios raw mode (8N1, no flow control, no echo, no
// line discipline), non-blocking, for poll()-driven reads.
//
// Baud rates: the standard termios rates (50 ... 921600 bit/s) use cfsetispeed/cfsetospeed; any
// other rate (250000, 1000000, 2000000, ...) is set exactly through termios2 with BOTHER
// (ioctl TCSETS2), which lives in serial_port_custom_baud.cpp because <asm/termbits.h> clashes
// with <termios.h>.
#pragma once

#include <string>

namespace vigs::drivers {

/// The termios Bxxx constant for a standard rate, or 0 when `baud` is not one of them.
[[nodiscard]] unsigned standard_baud_constant(int baud) noexcept;

/// Sets an arbitrary rate with termios2/BOTHER (both directions). Throws std::system_error.
void set_custom_baud(int fd, int baud);
/// The output rate the kernel reports through TCGETS2 (c_ospeed). Throws std::system_error.
[[nodiscard]] int read_termios2_baud(int fd);

class SerialPort {
 public:
  SerialPort() = default;
  /// Opens and configures `path`; throws std::system_error naming the path and the step that
  /// failed, or std::invalid_argument for a baud rate <= 0.
  static SerialPort open(const std::string& path, int baud);

  ~SerialPort();
  SerialPort(SerialPort&& other) noexcept;
  SerialPort& operator=(SerialPort&& other) noexcept;
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  [[nodiscard]] int fd() const noexcept { return fd_; }
  [[nodiscard]] bool is_open() const noexcept { return fd_ >= 0; }
  [[nodiscard]] const std::string& path() const noexcept { return path_; }
  void close() noexcept;

 private:
  int fd_ = -1;
  std::string path_;
};

}  // namespace vigs::drivers
