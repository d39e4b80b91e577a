// termios2 / BOTHER lives here alone: <asm/termbits.h> redefines struct termios and the B*
// constants of <termios.h>, so the two headers cannot share a translation unit.
#include "drivers/serial_imu/serial_port.hpp"

#include <asm/termbits.h>
#include <sys/ioctl.h>

#include <cerrno>
#include <system_error>

namespace vigs::drivers {

void set_custom_baud(int fd, int baud) {
  struct termios2 tio {};
  if (::ioctl(fd, TCGETS2, &tio) != 0) {
    throw std::system_error(errno, std::generic_category(), "ioctl TCGETS2");
  }
  tio.c_cflag &= ~static_cast<tcflag_t>(CBAUD);
  tio.c_cflag |= BOTHER;
  tio.c_cflag &= ~static_cast<tcflag_t>(CBAUD << IBSHIFT);
  tio.c_cflag |= BOTHER << IBSHIFT;
  tio.c_ispeed = static_cast<speed_t>(baud);
  tio.c_ospeed = static_cast<speed_t>(baud);
  if (::ioctl(fd, TCSETS2, &tio) != 0) {
    throw std::system_error(errno, std::generic_category(), "ioctl TCSETS2");
  }
}

int read_termios2_baud(int fd) {
  struct termios2 tio {};
  if (::ioctl(fd, TCGETS2, &tio) != 0) {
    throw std::system_error(errno, std::generic_category(), "ioctl TCGETS2");
  }
  return static_cast<int>(tio.c_ospeed);
}

}  // namespace vigs::drivers
