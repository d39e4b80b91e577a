// libFuzzer target: any byte string given to McapReader as a file must be read without a crash,
// leak or out-of-bounds access (ASan/UBSan), and every returned message must decode or throw
// DecodeError. Build and run: see tests/fuzz/CMakeLists.txt.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <string>

#include "io/mcap/mcap_reader.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/odometry.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/serial_chunk.hpp"
#include "io/ros_msgs/typed_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const int fd = ::memfd_create("vigs_fuzz_mcap", 0);
  if (fd < 0) return 0;
  if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, data, size, 0) != static_cast<ssize_t>(size)) {
    return 0;
  }
  const std::string path = "/proc/self/fd/" + std::to_string(fd);
  vigs::io::mcap::McapReader reader(path);
  vigs::io::mcap::MessageView m;
  while (reader.next(m)) {
    using namespace vigs::io::ros_msgs;
    try {
      Image image;
      Imu imu;
      CameraInfo info;
      PoseStamped pose;
      Odometry odom;
      SerialChunk serial;
      (void)(decode_message(m, image) || decode_message(m, imu) || decode_message(m, info) ||
             decode_message(m, pose) || decode_message(m, odom) || decode_message(m, serial));
    } catch (const DecodeError&) {
    }
  }
  return 0;
}
