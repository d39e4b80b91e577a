#pragma once
// Shared by the hostile-input tests: a private temporary folder, running `vigs` through a shell
// with its exit status (a signal is reported as 128 + signo, so a crash can never pass as exit
// 1), file reading, and crafted recordings written with the project's own MCAP writer (valid
// CRCs, so only the field under test is bad).
#include <stdlib.h>
#include <sys/wait.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <string>

#include "io/mcap/mcap_writer.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/typed_io.hpp"

namespace vigs::hostile {

class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "vigs_hostile_XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  [[nodiscard]] std::string file(const std::string& name) const { return (path_ / name).string(); }
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

/// Exit status of a shell command: 0..255, or 128 + signal when the program died of one.
inline int run_shell(const std::string& command) {
  const int status = std::system(command.c_str());
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
}

/// Runs `vigs ARGS` with stdout and stderr in `out` and `err`. The shell reports a child
/// killed by a signal as 128 + signo.
struct VigsRun {
  int status = -1;
  std::string out, err;
};
inline VigsRun vigs(const TempDir& dir, const std::string& args) {
  VigsRun r;
  const std::string o = dir.file("vigs.out"), e = dir.file("vigs.err");
  r.status = run_shell(std::string(VIGS_BIN) + " " + args + " > " + o + " 2> " + e);
  r.out = read_text(o);
  r.err = read_text(e);
  return r;
}

/// One RGB-D frame as the simulator writes it (topics of io/recording_topics.hpp), 8x6 rgb8 and
/// 16UC1 depth at 2 m, with a ground-truth pose and two IMU samples at rest.
struct CraftedFrame {
  io::ros_msgs::CameraInfo info;
  io::ros_msgs::Image rgb, depth;
  io::ros_msgs::PoseStamped pose;
  io::ros_msgs::Imu imu;
};

inline CraftedFrame good_frame(std::int64_t t_ns) {
  using namespace io::ros_msgs;
  CraftedFrame f;
  f.info.header.stamp = Time::from_ns(t_ns);
  f.info.width = 8;
  f.info.height = 6;
  f.info.k = {10, 0, 4, 0, 10, 3, 0, 0, 1};
  f.rgb.header = f.info.header;
  f.rgb.width = 8;
  f.rgb.height = 6;
  f.rgb.encoding = "rgb8";
  f.rgb.step = 24;
  f.rgb.data.assign(24 * 6, 128);
  f.depth = f.rgb;
  f.depth.encoding = "16UC1";
  f.depth.step = 16;
  f.depth.data.assign(16 * 6, 0);
  for (std::size_t i = 0; i < f.depth.data.size(); i += 2) f.depth.data[i + 1] = 2000 >> 8;
  for (std::size_t i = 0; i < f.depth.data.size(); i += 2) f.depth.data[i] = 2000 & 0xFF;
  f.pose.header = f.info.header;
  f.pose.pose.orientation.w = 1.0;
  f.imu.header = f.info.header;
  f.imu.linear_acceleration.z = 9.81;
  return f;
}

/// Writes `n` frames, each passed through `spoil(i, frame)` first, as a complete recording.
inline void write_recording(const std::string& path, int n,
                            const std::function<void(int, CraftedFrame&)>& spoil) {
  using namespace io::ros_msgs;
  io::mcap::McapWriterOptions opt;
  opt.profile = "ros2";
  io::mcap::McapWriter w(path, opt);
  const auto ch_info = add_channel<CameraInfo>(w, "/vigs/camera_info");
  const auto ch_rgb = add_channel<io::ros_msgs::Image>(w, "/vigs/rgb");
  const auto ch_depth = add_channel<io::ros_msgs::Image>(w, "/vigs/depth");
  const auto ch_imu = add_channel<Imu>(w, "/vigs/imu");
  const auto ch_pose = add_channel<PoseStamped>(w, "/vigs/ground_truth/body_pose");
  std::vector<std::uint8_t> buf;
  for (int i = 0; i < n; ++i) {
    const std::int64_t t = 1'000'000'000 + std::int64_t{i} * 50'000'000;
    CraftedFrame f = good_frame(t);
    spoil(i, f);
    const auto lt = static_cast<std::uint64_t>(t);
    write_message(w, ch_imu, lt, f.imu, buf);
    write_message(w, ch_pose, lt, f.pose, buf);
    write_message(w, ch_info, lt, f.info, buf);
    write_message(w, ch_rgb, lt, f.rgb, buf);
    write_message(w, ch_depth, lt, f.depth, buf);
  }
  w.close();
}

}  // namespace vigs::hostile
