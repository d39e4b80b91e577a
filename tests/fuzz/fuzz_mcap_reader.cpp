// libFuzzer target: any byte string given to McapReader as a file must be read without a crash,
// leak or out-of-bounds access (ASan/UBSan), and every returned message must decode or throw
// DecodeError, then pass or fail the range checks the tools apply (CameraInfo sizes and focal
// lengths, image step x height against the data, finite numbers) with an IoError, and an image
// that passes them must be walkable row by row. The first byte selects the reader options (bit
// 0: verify CRCs, so mutations inside chunks reach the decompressor and the decoders too); the
// rest is the file. Seeds: fuzz_mcap_seeds (a simulated recording and every message type).
#include <sys/mman.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <string>

#include "io/io_error.hpp"
#include "io/mcap/damage_report.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/message_checks.hpp"
#include "io/ros_msgs/odometry.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/serial_chunk.hpp"
#include "io/ros_msgs/typed_io.hpp"

namespace {

std::uint64_t g_sink = 0;  // keeps the row walk from being optimised away

void check_and_walk(const vigs::io::ros_msgs::Image& img) {
  const std::uint64_t bpp = img.encoding == "rgb8" || img.encoding == "bgr8" ? 3
                            : img.encoding == "16UC1"                        ? 2
                            : img.encoding == "32FC1"                        ? 4
                                                                             : 1;
  try {
    const std::uint64_t row = vigs::io::ros_msgs::check_image("fuzz", img, bpp);
    // The checks promise this walk stays inside the buffer.
    std::uint64_t sum = 0;
    for (std::uint64_t y = 0; y < img.height; ++y) sum += img.data[y * img.step + row - 1];
    __atomic_store_n(&g_sink, sum, __ATOMIC_RELAXED);
  } catch (const vigs::io::IoError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const int fd = ::memfd_create("vigs_fuzz_mcap", 0);
  if (fd < 0) return 0;
  if (::ftruncate(fd, 0) != 0 ||
      ::pwrite(fd, data + 1, size - 1, 0) != static_cast<ssize_t>(size - 1)) {
    return 0;
  }
  const std::string path = "/proc/self/fd/" + std::to_string(fd);
  vigs::io::mcap::McapReaderOptions options;
  options.verify_crcs = (data[0] & 1) != 0;
  vigs::io::mcap::McapReader reader(path, options);
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
      if (decode_message(m, image)) {
        check_and_walk(image);
      } else if (decode_message(m, info)) {
        try {
          check_camera_info("fuzz", info);
          if (!(info.k[0] > 0) || !std::isfinite(info.k[0])) __builtin_trap();
        } catch (const vigs::io::IoError&) {
        }
      } else {
        (void)(decode_message(m, imu) || decode_message(m, pose) || decode_message(m, odom) ||
               decode_message(m, serial));
      }
    } catch (const DecodeError&) {
    }
  }
  (void)vigs::io::mcap::damage_json(vigs::io::mcap::damage_of(reader), "fuzz");
  return 0;
}
