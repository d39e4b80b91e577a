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

}  // namespace

unsigned standard_baud_constant(int baud) noexcept {
  for (const BaudEntry& e : kStandardRates) {
    if (e.baud == baud) return static_cast<unsigned>(e.constant);
  }
  return 0;
}

const char* to_string(SerialOpenStep step) noexcept {
  switch (step) {
    case SerialOpenStep::kOpen:
      return "open";
    case SerialOpenStep::kGetAttributes:
      return "tcgetattr (not a tty?)";
    case SerialOpenStep::kSetSpeed:
      return "cfsetspeed";
    case SerialOpenStep::kSetAttributes:
      return "tcsetattr";
    case SerialOpenStep::kCustomBaud:
      return "custom baud (termios2 BOTHER)";
  }
  return "?";
}

int open_serial_fd(const char* path, int baud, SerialOpenStep& failed_step) noexcept {
  const int fd = ::open(path, O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    failed_step = SerialOpenStep::kOpen;
    return -1;
  }
  auto fail = [&](SerialOpenStep step, int err) {
    ::close(fd);
    errno = err;
    failed_step = step;
    return -1;
  };
  termios tio{};
  if (::tcgetattr(fd, &tio) != 0) return fail(SerialOpenStep::kGetAttributes, errno);
  ::cfmakeraw(&tio);  // 8 data bits, no parity, no echo, no canonical mode or signals
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~(CSTOPB | CRTSCTS);
  tio.c_iflag &= ~(IXON | IXOFF | IXANY);
  tio.c_cc[VMIN] = 0;  // read() returns what is there; poll() does the waiting
  tio.c_cc[VTIME] = 0;
  const unsigned standard = standard_baud_constant(baud);
  if (standard != 0 && (::cfsetispeed(&tio, static_cast<speed_t>(standard)) != 0 ||
                        ::cfsetospeed(&tio, static_cast<speed_t>(standard)) != 0)) {
    return fail(SerialOpenStep::kSetSpeed, errno);
  }
  if (::tcsetattr(fd, TCSANOW, &tio) != 0) return fail(SerialOpenStep::kSetAttributes, errno);
  if (standard == 0) {
    const int err = set_custom_baud_errno(fd, baud);
    if (err != 0) return fail(SerialOpenStep::kCustomBaud, err);
  }
  ::tcflush(fd, TCIFLUSH);  // stale bytes from before we opened carry no usable time
  return fd;
}

SerialPort SerialPort::open(const std::string& path, int baud) {
  if (baud <= 0) {
    throw std::invalid_argument("serial port " + path + ": baud rate " + std::to_string(baud) +
                                " must be positive");
  }
  SerialPort port;
  port.path_ = path;
  port.baud_ = baud;
  SerialOpenStep step{};
  port.fd_ = open_serial_fd(path.c_str(), baud, step);
  if (port.fd_ < 0) {
    std::string what = "serial port " + path + ": " + to_string(step);
    if (step == SerialOpenStep::kCustomBaud) what += " at " + std::to_string(baud) + " bit/s";
    throw std::system_error(errno, std::generic_category(), what);
  }
  return port;
}

bool SerialPort::reopen() noexcept {
  close();
  if (path_.empty() || baud_ <= 0) return false;
  SerialOpenStep step{};
  fd_ = open_serial_fd(path_.c_str(), baud_, step);
  return fd_ >= 0;
}

SerialPort::~SerialPort() {
  close();
}

SerialPort::SerialPort(SerialPort&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)), baud_(other.baud_), path_(std::move(other.path_)) {}

SerialPort& SerialPort::operator=(SerialPort&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = std::exchange(other.fd_, -1);
    baud_ = other.baud_;
    path_ = std::move(other.path_);
  }
  return *this;
}

void SerialPort::close() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace vigs::drivers
