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
/// The same without exceptions: 0, or the errno of the failing ioctl.
[[nodiscard]] int set_custom_baud_errno(int fd, int baud) noexcept;
/// The output rate the kernel reports through TCGETS2 (c_ospeed). Throws std::system_error.
[[nodiscard]] int read_termios2_baud(int fd);

enum class SerialOpenStep : unsigned char {
  kOpen,
  kGetAttributes,
  kSetSpeed,
  kSetAttributes,
  kCustomBaud
};
[[nodiscard]] const char* to_string(SerialOpenStep step) noexcept;

/// Opens and configures `path` without allocating or throwing (usable on a real-time thread):
/// the fd, or -1 with errno set and `failed_step` saying which step failed.
[[nodiscard]] int open_serial_fd(const char* path, int baud, SerialOpenStep& failed_step) noexcept;

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

  /// Closes and opens the same path again with the same settings (a USB adapter that was
  /// unplugged and re-enumerated under a stable name). No allocation; false if it failed.
  bool reopen() noexcept;

  [[nodiscard]] int fd() const noexcept { return fd_; }
  [[nodiscard]] bool is_open() const noexcept { return fd_ >= 0; }
  [[nodiscard]] const std::string& path() const noexcept { return path_; }
  void close() noexcept;

 private:
  int fd_ = -1;
  int baud_ = 0;
  std::string path_;
};

}  // namespace vigs::drivers
