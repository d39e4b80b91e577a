// `vigs record` as a real process on real sources: an .oni clip played by real OpenNI2 and an
// EuRoC IMU played as Xsens bytes on a pseudo-terminal (`vigs imu play`) read by the real serial
// driver. The file is then opened by VIGS's reader (`vigs mcap info --decode`) and by the
// official TypeScript MCAP readers (tests/conformance/summarize_mcap.mjs); a recording killed
// with SIGKILL stays readable up to its last chunk, and `vigs replay --allow-truncated` replays it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "../common/temp_files.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/oni/oni_clip_writer.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/serial_chunk.hpp"
#include "io/ros_msgs/time_reference.hpp"
#include "io/ros_msgs/typed_io.hpp"
#include "record/recorder.hpp"
#include "tests/common/cli_process.hpp"

namespace vigs::drivers {
namespace {

// Removed when the test program exits, passed or failed.
std::string temp_path(const std::string& name) {
  static vigs::test::TempFiles files("record");
  return files.path(name);
}

using test_cli::run_output;

std::uint64_t json_u64(const std::string& text, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(text, m, std::regex("\"" + key + "\": (\\d+)"))) return ~0ull;
  return std::stoull(m[1]);
}

constexpr std::uint32_t kW = 64, kH = 48;
constexpr int kFrames = 30;

std::string write_clip() {
  const std::string path = temp_path("clip.oni");
  io::oni::OniClipWriter writer(path, {kW, kH, 30});
  std::vector<std::uint16_t> depth(kW * kH);
  std::vector<std::uint8_t> rgb(kW * kH * 3);
  for (int f = 0; f < kFrames; ++f) {
    for (auto& d : depth) d = static_cast<std::uint16_t>(1000 + f);
    for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<std::uint8_t>(10 + f + i % 3);
    writer.add_frame(depth, rgb);
  }
  writer.close();
  return path;
}

std::string write_csv(int rows) {
  const std::string csv = temp_path("imu.csv");
  std::ifstream in(std::string(VIGS_SHARED_DATA_DIR) + "/euroc_v102/imu0.csv");
  std::ofstream out(csv);
  std::string line;
  for (int r = 0; r <= rows && std::getline(in, line); ++r) out << line << "\n";
  return csv;
}

// Starts `vigs imu play`; returns the process and its pty.
std::pair<FILE*, std::string> start_imu_play(const std::string& csv, double delay_s) {
  FILE* play = ::popen(
      (std::string(VIGS_BIN) + " imu play " + csv + " --delay " + std::to_string(delay_s)).c_str(),
      "r");
  if (play == nullptr) return {nullptr, ""};
  char first[512] = {};
  if (std::fgets(first, sizeof first, play) == nullptr) return {play, ""};
  std::smatch m;
  const std::string head = first;
  if (!std::regex_search(head, m, std::regex("\"pty\": \"([^\"]+)\""))) return {play, ""};
  return {play, m[1].str()};
}

std::string write_robot(const std::string& clip, const std::string& pty) {
  const std::string path = temp_path("robot.yaml");
  std::ofstream(path) << "camera:\n  driver: openni2\n  device: " << clip
                      << "\n  width_px: 64\n  height_px: 48\n  fx_px: 50\n  fy_px: 50\n"
                         "  cx_px: 32\n  cy_px: 24\n  rate_hz: 30\n"
                         "imu:\n  driver: serial\n  port: "
                      << pty << "\nrt:\n  realtime_priorities: false\n  pin_cpus: false\n";
  return path;
}

TEST(RecordCli, RecordsTheOniAndPtySourcesIntoAnMcapTheOfficialReaderOpens) {
  const std::string clip = write_clip();
  constexpr int kRows = 400;  // 2 s of 200 Hz IMU
  // The delay leaves `vigs record` time to open the pty before the first byte (bytes written
  // before the serial driver opens and configures the port are flushed), even on a loaded machine.
  auto [play, pty] = start_imu_play(write_csv(kRows), 2.5);
  ASSERT_NE(play, nullptr);
  ASSERT_FALSE(pty.empty());
  const std::string robot = write_robot(clip, pty);
  const std::string out = temp_path("rec.mcap");
  const auto [summary, status] = run_output(std::string(VIGS_BIN) + " record --config " + robot +
                                            " --out " + out + " --seconds 6");
  char buf[4096];
  while (std::fgets(buf, sizeof buf, play) != nullptr) {
  }
  ::pclose(play);
  ASSERT_EQ(status, 0) << summary;
  const std::uint64_t frames = json_u64(summary, "frames");
  const std::uint64_t drops = json_u64(summary, "tap_drops");
  EXPECT_GE(frames, 1u) << summary;
  EXPECT_EQ(frames + drops, static_cast<std::uint64_t>(kFrames)) << summary;
  // Every sample the driver stamped and every byte it read is in the file. (On a loaded machine
  // the first bytes can reach the pty before the driver opened it; they are then not the
  // recorder's to lose.)
  const std::uint64_t imu_samples = json_u64(summary, "imu_samples");
  EXPECT_EQ(imu_samples, json_u64(summary, "imu_driver_samples")) << summary;
  EXPECT_EQ(json_u64(summary, "serial_bytes"), json_u64(summary, "serial_bytes_read")) << summary;
  EXPECT_GE(imu_samples, static_cast<std::uint64_t>(kRows / 2)) << summary;
  EXPECT_LE(imu_samples, static_cast<std::uint64_t>(kRows)) << summary;
  EXPECT_NE(summary.find("\"camera_fault\": \"none\""), std::string::npos) << summary;

  // VIGS's own reader: every chunk CRC and message decodes, no issue.
  const auto [info, info_status] =
      run_output(std::string(VIGS_BIN) + " mcap info " + out + " --decode");
  EXPECT_EQ(info_status, 0) << info;
  EXPECT_NE(info.find("\"topic\": \"/vigs/imu/serial\", \"schema\": \"vigs_msgs/msg/SerialChunk\""),
            std::string::npos)
      << info;

  // The official TypeScript readers (indexed + stream, CRCs validated, ROS 2 decoders).
  if (std::system("command -v node >/dev/null 2>&1") != 0) GTEST_SKIP() << "node not installed";
  const auto [ts, ts_status] = run_output("node " + std::string(VIGS_SOURCE_DIR) +
                                          "/tests/conformance/summarize_mcap.mjs " + out);
  ASSERT_EQ(ts_status, 0) << ts;
  const std::regex rgb(
      R"("/vigs/rgb":\{"schema":"sensor_msgs/msg/Image","messages":(\d+),"first_log_time":"\d+","first":\{"width":64,"height":48,"encoding":"rgb8","bytes":9216,"data0":(\d+),"data1":(\d+)\})");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(ts, m, rgb)) << ts;
  EXPECT_EQ(std::stoull(m[1]), frames);
  const int first_frame = std::stoi(m[2]) - 10;  // R of frame f is 10 + f
  EXPECT_EQ(std::stoi(m[3]), 10 + first_frame + 1);
  EXPECT_NE(ts.find(R"("encoding":"16UC1","bytes":6144,"data0":)" +
                    std::to_string((1000 + first_frame) & 0xFF) + R"(,"data1":3)"),
            std::string::npos)
      << ts;
  EXPECT_NE(ts.find(R"("/vigs/imu":{"schema":"sensor_msgs/msg/Imu","messages":)" +
                    std::to_string(imu_samples)),
            std::string::npos)
      << ts;
  EXPECT_NE(ts.find(R"("/vigs/camera_info":{"schema":"sensor_msgs/msg/CameraInfo","messages":)" +
                    std::to_string(frames)),
            std::string::npos)
      << ts;
  EXPECT_NE(ts.find(R"("first":{"port":")" + pty + "\""), std::string::npos) << ts;
}

TEST(RecordCli, SigkillLeavesAFileReadableToItsLastChunk) {
  const std::string clip = write_clip();
  auto [play, pty] = start_imu_play(write_csv(800), 0.8);  // 4 s of IMU
  ASSERT_NE(play, nullptr);
  ASSERT_FALSE(pty.empty());
  const std::string robot = write_robot(clip, pty);
  const std::string out = temp_path("killed.mcap");
  const auto [kill_out, kill_status] = run_output(
      "sh -c '" + std::string(VIGS_BIN) + " record --config " + robot + " --out " + out +
      " --seconds 60 >/dev/null & pid=$!; sleep 3.2; kill -9 $pid; wait $pid; echo rc=$?'");
  char buf[4096];
  while (std::fgets(buf, sizeof buf, play) != nullptr) {
  }
  ::pclose(play);
  EXPECT_NE(kill_out.find("rc=137"), std::string::npos) << kill_out;  // died by SIGKILL
  const auto [info, info_status] =
      run_output(std::string(VIGS_BIN) + " mcap info " + out + " --decode");
  EXPECT_EQ(info_status, 1) << info;  // damage reported ...
  EXPECT_NE(info.find("\"summary\": false"), std::string::npos) << info;
  // ... but every chunk before the kill is there: chunks close each second of log time.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      info, m,
      std::regex(
          R"("topic": "/vigs/imu", "schema": "sensor_msgs/msg/Imu", "message_encoding": "cdr", "messages": (\d+))")))
      << info;
  EXPECT_GE(std::stoi(m[1]), 200) << info;
  EXPECT_NE(info.find("\"decode_errors\": 0"), std::string::npos) << info;

  // `vigs replay` refuses the prefix naming the damage; with --allow-truncated it replays it
  // and says what it found.
  const std::string results = temp_path("killed_results");
  const std::string replay = std::string(VIGS_BIN) + " replay " + out + " --quiet --out " + results;
  const auto [refused, refused_status] = run_output(replay);
  EXPECT_EQ(refused_status, 1) << refused;
  EXPECT_NE(refused.find("--allow-truncated"), std::string::npos) << refused;
  const auto [allowed, allowed_status] = run_output(replay + " --allow-truncated");
  EXPECT_EQ(allowed_status, 0) << allowed;
  EXPECT_NE(allowed.find("damaged recording (truncated"), std::string::npos) << allowed;
  EXPECT_EQ(::access((results + "/trajectory.tum").c_str(), R_OK), 0) << allowed;
}

TEST(Recorder, WritesEdgesSerialBytesAndImuAsTheirMessages) {
  const std::string out = temp_path("unit.mcap");
  rt::SpscRing<drivers::TriggerEdge> edges(8);
  rt::SpscRing<drivers::SerialBytes> bytes(8);
  rt::SpscRing<ImuSample> imu(8);
  record::Recorder rec(out);
  rec.add_edges(edges, "gpiochip0:17");
  rec.add_serial(bytes, "/dev/ttyUSB0");
  rec.add_imu(imu);
  rec.open();
  ASSERT_TRUE(edges.try_push({1'000'000'123, 0}));
  ASSERT_TRUE(edges.try_push({1'033'333'456, 1}));
  const std::uint8_t raw[5] = {0xFA, 0xFF, 0x36, 0x00, 0x42};
  ASSERT_TRUE(bytes.try_emplace(1'010'000'000, raw, sizeof raw));
  ImuSample s;
  s.t_ns = 1'020'000'000;
  s.accel_mps2[2] = 9.81;
  s.gyro_rps[0] = 0.25;
  ASSERT_TRUE(imu.try_push(s));
  rec.drain_once();
  rec.stop();
  EXPECT_EQ(rec.stats().edges, 2u);
  EXPECT_EQ(rec.stats().serial_bytes, 5u);

  io::mcap::McapReader r(out);
  io::mcap::MessageView m;
  std::vector<io::ros_msgs::TimeReference> refs;
  int imu_msgs = 0, chunks = 0;
  while (r.next(m)) {
    io::ros_msgs::TimeReference ref;
    io::ros_msgs::SerialChunk chunk;
    io::ros_msgs::Imu i;
    if (io::ros_msgs::decode_message(m, ref)) {
      EXPECT_EQ(m.channel->topic, record::kTriggerTopic);
      EXPECT_EQ(static_cast<std::int64_t>(m.log_time_ns), ref.time_ref.to_ns());
      refs.push_back(ref);
    } else if (io::ros_msgs::decode_message(m, chunk)) {
      EXPECT_EQ(chunk.port, "/dev/ttyUSB0");
      EXPECT_EQ(chunk.data, std::vector<std::uint8_t>(raw, raw + 5));
      EXPECT_EQ(chunk.stamp.to_ns(), 1'010'000'000);
      ++chunks;
    } else if (io::ros_msgs::decode_message(m, i)) {
      EXPECT_EQ(i.linear_acceleration.z, 9.81);
      EXPECT_EQ(i.angular_velocity.x, 0.25);
      EXPECT_EQ(i.header.stamp.to_ns(), 1'020'000'000);
      ++imu_msgs;
    }
  }
  EXPECT_TRUE(r.issues().empty());
  ASSERT_EQ(refs.size(), 2u);
  EXPECT_EQ(refs[0].time_ref.to_ns(), 1'000'000'123);
  EXPECT_EQ(refs[1].header.stamp.to_ns(), 1'033'333'456);
  EXPECT_EQ(refs[1].source, "gpiochip0:17");
  EXPECT_EQ(chunks, 1);
  EXPECT_EQ(imu_msgs, 1);
}

TEST(RecordCli, TheRealsenseRobotFailsNamingItsMissingDeviceAndLeavesNoFile) {
  const std::string out = temp_path("rs.mcap");
  const auto [text, status] =
      run_output(std::string(VIGS_BIN) + " record --config " + std::string(VIGS_SOURCE_DIR) +
                 "/firmware_config/robots/realsense_v4l2_gpio.yaml --out " + out + " --seconds 1");
  EXPECT_EQ(status, 1) << text;
  EXPECT_NE(text.find("GPIO line 17 of 'gpiochip0'"), std::string::npos) << text;
  EXPECT_NE(::access(out.c_str(), F_OK), 0) << "a failed start leaves no recording";
}

TEST(RecordCli, NothingToRecordIsAnErrorNamingTheConfig) {
  const std::string robot = temp_path("empty.yaml");
  std::ofstream(robot) << "camera:\n  driver: replay\n";
  const auto [out, status] = run_output(std::string(VIGS_BIN) + " record --config " + robot +
                                        " --out " + temp_path("x.mcap"));
  EXPECT_EQ(status, 1) << out;
  EXPECT_NE(out.find(robot + ": nothing to record"), std::string::npos) << out;
}

}  // namespace
}  // namespace vigs::drivers
