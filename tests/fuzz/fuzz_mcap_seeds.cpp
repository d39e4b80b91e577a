// Writes seed inputs for fuzz_mcap_reader into a corpus directory (argument 1): a short simulated
// recording (the simulator at 32x24 px, 0.3 s: colour, depth, CameraInfo, IMU, ground truth),
// the same messages in uncompressed chunks, and one message of every type in ros1 encoding.
// Each seed is written twice, with the target's first byte selecting CRC checks on and off.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "core/config/robot_config.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/mcap/mcap_writer.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/odometry.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/serial_chunk.hpp"
#include "io/ros_msgs/typed_io.hpp"
#include "sim/mcap_sink.hpp"
#include "sim/simulator.hpp"

namespace {

namespace fs = std::filesystem;
using namespace vigs;

std::vector<char> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Copies every message of `in` into `out` with uncompressed, small chunks.
void rewrite_uncompressed(const std::string& in, const std::string& out) {
  io::mcap::McapReader reader(in);
  io::mcap::McapWriterOptions opt;
  opt.compression = io::mcap::Compression::kNone;
  opt.chunk_size_bytes = 16 << 10;
  io::mcap::McapWriter writer(out, opt);
  std::map<std::uint16_t, std::uint16_t> channel_of;
  io::mcap::MessageView m;
  while (reader.next(m)) {
    auto it = channel_of.find(m.channel->id);
    if (it == channel_of.end()) {
      const std::uint16_t schema =
          m.schema ? writer.add_schema(m.schema->name, m.schema->encoding, m.schema->text()) : 0;
      it = channel_of
               .emplace(m.channel->id,
                        writer.add_channel(m.channel->topic, schema, m.channel->message_encoding))
               .first;
    }
    writer.write(it->second, m.log_time_ns, m.publish_time_ns, m.data);
  }
  writer.close();
}

void write_every_type_ros1(const std::string& path) {
  using namespace io::ros_msgs;
  io::mcap::McapWriterOptions opt;
  opt.profile = "ros1";
  io::mcap::McapWriter w(path, opt);
  std::vector<std::uint8_t> buf;
  Image img;
  img.width = 2;
  img.height = 2;
  img.encoding = "mono8";
  img.step = 2;
  img.data = {1, 2, 3, 4};
  CameraInfo info;
  info.width = info.height = 2;
  info.k = {1, 0, 1, 0, 1, 1, 0, 0, 1};
  Imu imu;
  imu.linear_acceleration.z = 9.81;
  PoseStamped pose;
  pose.pose.orientation.w = 1;
  Odometry odom;
  odom.pose.orientation.w = 1;
  SerialChunk serial;
  serial.data = {0xFA, 0xFF, 0x36, 0x00};
  const Encoding e = Encoding::kRos1;
  write_message(w, add_channel<Image>(w, "/img", e), 1, img, buf, e);
  write_message(w, add_channel<CameraInfo>(w, "/info", e), 2, info, buf, e);
  write_message(w, add_channel<Imu>(w, "/imu", e), 3, imu, buf, e);
  write_message(w, add_channel<PoseStamped>(w, "/pose", e), 4, pose, buf, e);
  write_message(w, add_channel<Odometry>(w, "/odom", e), 5, odom, buf, e);
  write_message(w, add_channel<SerialChunk>(w, "/serial", e), 6, serial, buf, e);
  w.close();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: fuzz_mcap_seeds CORPUS_DIR\n";
    return 2;
  }
  const fs::path dir = argv[1];
  fs::create_directories(dir);
  const std::string sim = (dir / "sim.tmp").string(), raw = (dir / "raw.tmp").string(),
                    ros1 = (dir / "ros1.tmp").string();
  config::RobotConfig cfg;
  cfg.camera.width_px = 32;
  cfg.camera.height_px = 24;
  cfg.camera.fx_px = cfg.camera.fy_px = 16.0;
  cfg.camera.cx_px = 16.0;
  cfg.camera.cy_px = 12.0;
  cfg.sim.humans = 0;
  cfg.sim.seconds = 0.3;
  cfg.sim.render_threads = 1;
  {
    sim::Simulator simulator(cfg);
    sim::McapSinkOptions opt;
    opt.imu = cfg.imu;
    sim::McapSink sink(sim, opt);
    simulator.run(sink);
    sink.close();
  }
  rewrite_uncompressed(sim, raw);
  write_every_type_ros1(ros1);
  int index = 0;
  for (const std::string& file : {sim, raw, ros1}) {
    const std::vector<char> bytes = read_bytes(file);
    for (const char selector : {'\x01', '\x00'}) {
      std::ofstream out(dir / ("seed_" + std::to_string(index++)), std::ios::binary);
      out.put(selector);
      out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    }
    fs::remove(file);
  }
  std::cout << "fuzz_mcap_seeds: " << index << " seeds in " << dir.string() << "\n";
  return 0;
}
