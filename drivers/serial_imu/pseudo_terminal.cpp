#include "drivers/serial_imu/pseudo_terminal.hpp"

#include <fcntl.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>

namespace vigs::drivers {

PseudoTerminal::PseudoTerminal() {
  master_ = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master_ < 0 || ::grantpt(master_) != 0 || ::unlockpt(master_) != 0) {
    const int err = errno;
    close_master();
    throw std::system_error(err, std::generic_category(), "posix_openpt/grantpt/unlockpt");
  }
  const char* name = ::ptsname(master_);
  if (name == nullptr) {
    const int err = errno;
    close_master();
    throw std::system_error(err, std::generic_category(), "ptsname");
  }
  slave_path_ = name;
  slave_ = ::open(name, O_RDWR | O_NOCTTY);
  termios tio{};
  bool raw = slave_ >= 0 && ::tcgetattr(slave_, &tio) == 0;
  if (raw) {
    ::cfmakeraw(&tio);
    raw = ::tcsetattr(slave_, TCSANOW, &tio) == 0;
  }
  if (!raw) {
    const int err = errno;
    if (slave_ >= 0) ::close(slave_);
    close_master();
    throw std::system_error(err, std::generic_category(), "open raw " + slave_path_);
  }
}

PseudoTerminal::~PseudoTerminal() {
  close_master();
  if (slave_ >= 0) ::close(slave_);
}

bool PseudoTerminal::write_all(std::span<const std::uint8_t> bytes) const noexcept {
  std::size_t done = 0;
  while (done < bytes.size()) {
    if (master_ < 0) return false;
    const ssize_t n = ::write(master_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

void PseudoTerminal::close_master() noexcept {
  if (master_ >= 0) ::close(master_);
  master_ = -1;
}

}  // namespace vigs::drivers
