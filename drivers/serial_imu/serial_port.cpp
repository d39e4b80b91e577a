#include "drivers/serial_imu/serial_port.hpp"

#include <fcntl.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <stdexcept>
#include <system_error>
#include <utility>

namespace vigs::drivers {
namespace {

struct BaudEntry {
  int baud;
  speed_t constant;
};

constexpr BaudEntry kStandardRates[] = {
    {50, B50},         {75, B75},         {110, B110},       {134, B134},       {150, B150},
    {200, B200},       {300, B300},       {600, B600},       {1200, B1200},     {1800, B1800},
    {2400, B2400},     {4800, B4800},     {9600, B9600},     {19200, B19200},   {38400, B38400},
    {57600, B57600},   {115200, B115200}, {230400, B230400}, {460800, B460800}, {500000, B500000},
    {576000, B576000}, {921600, B921600},
};

[[noreturn]] void throw_errno(const std::string& path, const char* step) {
  throw std::system_error(errno, std::generic_category(), "serial port " + path + ": " + step);
}

}  // namespace

unsigned standard_baud_constant(int baud) noexcept {
  for (const BaudEntry& e : kStandardRates) {
    if (e.baud == baud) return static_cast<unsigned>(e.constant);
  }
  return 0;
}

SerialPort SerialPort::open(const std::string& path, int baud) {
  if (baud <= 0) {
    throw std::invalid_argument("serial port " + path + ": baud rate " + std::to_string(baud) +
                                " must be positive");
  }
  SerialPort port;
  port.path_ = path;
  port.fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (port.fd_ < 0) throw_errno(path, "open");

  termios tio{};
  if (::tcgetattr(port.fd_, &tio) != 0) throw_errno(path, "tcgetattr (not a tty?)");
  ::cfmakeraw(&tio);  // 8 data bits, no parity, no echo, no canonical mode or signals
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~(CSTOPB | CRTSCTS);
  tio.c_iflag &= ~(IXON | IXOFF | IXANY);
  tio.c_cc[VMIN] = 0;  // read() returns what is there; poll() does the waiting
  tio.c_cc[VTIME] = 0;
  const unsigned standard = standard_baud_constant(baud);
  if (standard != 0) {
    if (::cfsetispeed(&tio, static_cast<speed_t>(standard)) != 0 ||
        ::cfsetospeed(&tio, static_cast<speed_t>(standard)) != 0) {
      throw_errno(path, "cfsetspeed");
    }
  }
  if (::tcsetattr(port.fd_, TCSANOW, &tio) != 0) throw_errno(path, "tcsetattr");
  if (standard == 0) {
    try {
      set_custom_baud(port.fd_, baud);
    } catch (const std::system_error& e) {
      throw std::system_error(e.code(), "serial port " + path + ": custom baud " +
                                            std::to_string(baud) + " (termios2 BOTHER)");
    }
  }
  ::tcflush(port.fd_, TCIFLUSH);  // stale bytes from before we opened carry no usable time
  return port;
}

SerialPort::~SerialPort() {
  close();
}

SerialPort::SerialPort(SerialPort&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), path_(std::move(other.path_)) {}

SerialPort& SerialPort::operator=(SerialPort&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = std::exchange(other.fd_, -1);
    path_ = std::move(other.path_);
  }
  return *this;
}

void SerialPort::close() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace vigs::drivers
