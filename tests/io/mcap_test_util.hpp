#pragma once
// Writes a recording holding every message type and remembers what went in, for the MCAP tests.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "io/mcap/mcap_reader.hpp"
#include "io/mcap/mcap_writer.hpp"
#include "io/ros_msgs/typed_io.hpp"
#include "msg_samples.hpp"

namespace vigs::io::test {

struct Written {
  std::string topic;
  std::uint64_t log_time_ns = 0;
  std::vector<std::uint8_t> data;
  bool operator==(const Written&) const = default;
};

inline std::filesystem::path temp_dir() {
  return std::filesystem::temp_directory_path() / ("vigs_io_test_" + std::to_string(::getpid()));
}

/// Removes this process's temporary folder when the test program exits.
struct TempDirCleanup {
  ~TempDirCleanup() {
    std::error_code ec;
    std::filesystem::remove_all(temp_dir(), ec);
  }
};
inline const TempDirCleanup kTempDirCleanup;

inline std::string temp_path(const std::string& name) {
  const auto dir = temp_dir();
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

/// `rounds` rounds of one message of each type (6 channels), log times 1 ms apart.
inline std::vector<Written> write_all_types(const std::string& path, ros_msgs::Encoding encoding,
                                            int rounds, mcap::McapWriterOptions options = {}) {
  using namespace ros_msgs;
  options.profile = encoding == Encoding::kCdr ? "ros2" : "ros1";
  mcap::McapWriter w(path, options);
  const auto rgb = add_channel<Image>(w, "/tesse/left_cam/rgb/image_raw", encoding);
  const auto depth = add_channel<Image>(w, "/tesse/depth_cam/mono/image_raw", encoding);
  const auto imu = add_channel<Imu>(w, "/tesse/imu/clean/imu", encoding);
  const auto info = add_channel<CameraInfo>(w, "/tesse/left_cam/camera_info", encoding);
  const auto pose = add_channel<PoseStamped>(w, "/vigs/ground_truth", encoding);
  const auto serial = add_channel<SerialChunk>(w, "/vigs/serial_imu", encoding);
  std::vector<Written> out;
  std::vector<std::uint8_t> buf;
  std::uint64_t t = 1'000'000'000;
  auto put = [&](std::uint16_t ch, const std::string& topic, const auto& msg) {
    write_message(w, ch, t, msg, buf, encoding);
    out.push_back({topic, t, buf});
    t += 1'000'000;
  };
  for (int i = 0; i < rounds; ++i) {
    put(rgb, "/tesse/left_cam/rgb/image_raw", sample_image(i, false));
    put(depth, "/tesse/depth_cam/mono/image_raw", sample_image(i, true));
    put(imu, "/tesse/imu/clean/imu", sample_imu(i));
    put(info, "/tesse/left_cam/camera_info", sample_camera_info(i));
    put(pose, "/vigs/ground_truth", sample_pose(i));
    put(serial, "/vigs/serial_imu", sample_serial(i));
  }
  w.close();
  return out;
}

inline std::vector<Written> read_all(mcap::McapReader& r) {
  std::vector<Written> out;
  mcap::MessageView m;
  while (r.next(m))
    out.push_back({m.channel->topic, m.log_time_ns, {m.data.begin(), m.data.end()}});
  return out;
}

inline std::vector<std::uint8_t> load(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

inline void save(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

}  // namespace vigs::io::test
