// termios2 / BOTHER lives here alone: <asm/termbits.h> redefines struct termios and the B*
// constants of <termios.h>, so the two headers cannot share a translation unit.
#include "drivers/serial_imu/serial_port.hpp"

#include <asm/termbits.h>
#include <sys/ioctl.h>

#include <cerrno>
#include <system_error>

namespace vigs::drivers {

int set_custom_baud_errno(int fd, int baud) noexcept {
  struct termios2 tio {};
  if (::ioctl(fd, TCGETS2, &tio) != 0) return errno;
  tio.c_cflag &= ~static_cast<tcflag_t>(CBAUD);
  tio.c_cflag |= BOTHER;
  tio.c_cflag &= ~static_cast<tcflag_t>(CBAUD << IBSHIFT);
  tio.c_cflag |= BOTHER << IBSHIFT;
  tio.c_ispeed = static_cast<speed_t>(baud);
  tio.c_ospeed = static_cast<speed_t>(baud);
  if (::ioctl(fd, TCSETS2, &tio) != 0) return errno;
  return 0;
}

void set_custom_baud(int fd, int baud) {
  const int err = set_custom_baud_errno(fd, baud);
  if (err != 0) throw std::system_error(err, std::generic_category(), "termios2 BOTHER");
}

int read_termios2_baud(int fd) {
  struct termios2 tio {};
  if (::ioctl(fd, TCGETS2, &tio) != 0) {
    throw std::system_error(errno, std::generic_category(), "ioctl TCGETS2");
  }
  return static_cast<int>(tio.c_ospeed);
}

}  // namespace vigs::drivers
