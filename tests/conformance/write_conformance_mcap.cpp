// Writes an MCAP file with every project message type through vigs_io, and the expected decoded
// values as JSON (ROS field names), for read_mcap.mjs to compare against the official TypeScript
// MCAP reader and Foxglove's ROS decoders.
//   write_conformance_mcap cdr|ros1 OUT.mcap OUT.json [--ascii]
// (--ascii leaves out the one non-ASCII string, see run_conformance.sh)
// and compares a file re-written by the official TypeScript writer (write_mcap.mjs) with ours:
//   write_conformance_mcap compare OURS.mcap THEIRS.mcap
#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "../io/msg_samples.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/mcap/mcap_writer.hpp"
#include "io/ros_msgs/typed_io.hpp"

namespace {

using namespace vigs::io;
using ros_msgs::Encoding;

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof(b), "%.17g", v);
  return b;
}
std::string str(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o + "\"";
}
template <class C>
std::string arr(const C& c) {
  std::string o = "[";
  for (std::size_t i = 0; i < c.size(); ++i) o += (i ? "," : "") + num(static_cast<double>(c[i]));
  return o + "]";
}

struct Json {
  Encoding e;
  std::string time(const ros_msgs::Time& t) const {
    return "{\"sec\":" + std::to_string(t.sec) +
           (e == Encoding::kCdr ? ",\"nanosec\":" : ",\"nsec\":") + std::to_string(t.nanosec) + "}";
  }
  std::string header(const ros_msgs::Header& h) const {
    std::string o = "{";
    if (e == Encoding::kRos1) o += "\"seq\":" + std::to_string(h.seq) + ",";
    return o + "\"stamp\":" + time(h.stamp) + ",\"frame_id\":" + str(h.frame_id) + "}";
  }
  static std::string xyz(double x, double y, double z) {
    return "{\"x\":" + num(x) + ",\"y\":" + num(y) + ",\"z\":" + num(z) + "}";
  }
  static std::string quat(const ros_msgs::Quaternion& q) {
    return "{\"x\":" + num(q.x) + ",\"y\":" + num(q.y) + ",\"z\":" + num(q.z) +
           ",\"w\":" + num(q.w) + "}";
  }
  std::string operator()(const ros_msgs::Image& m) const {
    return "{\"header\":" + header(m.header) + ",\"height\":" + std::to_string(m.height) +
           ",\"width\":" + std::to_string(m.width) + ",\"encoding\":" + str(m.encoding) +
           ",\"is_bigendian\":" + std::to_string(m.is_bigendian) +
           ",\"step\":" + std::to_string(m.step) + ",\"data\":" + arr(m.data) + "}";
  }
  std::string operator()(const ros_msgs::Imu& m) const {
    return "{\"header\":" + header(m.header) + ",\"orientation\":" + quat(m.orientation) +
           ",\"orientation_covariance\":" + arr(m.orientation_covariance) +
           ",\"angular_velocity\":" +
           xyz(m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z) +
           ",\"angular_velocity_covariance\":" + arr(m.angular_velocity_covariance) +
           ",\"linear_acceleration\":" +
           xyz(m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z) +
           ",\"linear_acceleration_covariance\":" + arr(m.linear_acceleration_covariance) + "}";
  }
  std::string operator()(const ros_msgs::CameraInfo& m) const {
    const bool r1 = e == Encoding::kRos1;  // ROS 1 names the arrays D K R P
    return "{\"header\":" + header(m.header) + ",\"height\":" + std::to_string(m.height) +
           ",\"width\":" + std::to_string(m.width) +
           ",\"distortion_model\":" + str(m.distortion_model) + (r1 ? ",\"D\":" : ",\"d\":") +
           arr(m.d) + (r1 ? ",\"K\":" : ",\"k\":") + arr(m.k) + (r1 ? ",\"R\":" : ",\"r\":") +
           arr(m.r) + (r1 ? ",\"P\":" : ",\"p\":") + arr(m.p) +
           ",\"binning_x\":" + std::to_string(m.binning_x) +
           ",\"binning_y\":" + std::to_string(m.binning_y) +
           ",\"roi\":{\"x_offset\":" + std::to_string(m.roi.x_offset) +
           ",\"y_offset\":" + std::to_string(m.roi.y_offset) +
           ",\"height\":" + std::to_string(m.roi.height) +
           ",\"width\":" + std::to_string(m.roi.width) +
           ",\"do_rectify\":" + (m.roi.do_rectify ? "true" : "false") + "}}";
  }
  std::string operator()(const ros_msgs::PoseStamped& m) const {
    return "{\"header\":" + header(m.header) + ",\"pose\":{\"position\":" +
           xyz(m.pose.position.x, m.pose.position.y, m.pose.position.z) +
           ",\"orientation\":" + quat(m.pose.orientation) + "}}";
  }
  std::string operator()(const ros_msgs::Odometry& m) const {
    return "{\"header\":" + header(m.header) + ",\"child_frame_id\":" + str(m.child_frame_id) +
           ",\"pose\":{\"pose\":{\"position\":" +
           xyz(m.pose.position.x, m.pose.position.y, m.pose.position.z) +
           ",\"orientation\":" + quat(m.pose.orientation) +
           "},\"covariance\":" + arr(m.pose_covariance) + "},\"twist\":{\"twist\":{\"linear\":" +
           xyz(m.linear_velocity.x, m.linear_velocity.y, m.linear_velocity.z) +
           ",\"angular\":" + xyz(m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z) +
           "},\"covariance\":" + arr(m.twist_covariance) + "}}";
  }
  std::string operator()(const ros_msgs::SerialChunk& m) const {
    return "{\"stamp\":" + time(m.stamp) + ",\"port\":" + str(m.port) + ",\"data\":" + arr(m.data) +
           "}";
  }
};

// Decodes both messages as Msg; nullopt if `a` is not a Msg.
template <class Msg>
std::optional<bool> same_as(const mcap::MessageView& a, const mcap::MessageView& b) {
  Msg x, y;
  if (!ros_msgs::decode_message(a, x)) return std::nullopt;
  return ros_msgs::decode_message(b, y) && x == y;
}

// Reads both files with the VIGS reader; every message must match in channel, times, sequence
// and every decoded field. Returns the process exit code.
int compare(const char* ours_path, const char* theirs_path) {
  mcap::McapReader ours(ours_path), theirs(theirs_path);
  mcap::MessageView a, b;
  int n = 0, identical_bytes = 0, bad = 0;
  auto fail = [&](const std::string& what) {
    if (++bad <= 10) std::fprintf(stderr, "message %d: %s\n", n, what.c_str());
  };
  for (;; ++n) {
    const bool more_a = ours.next(a), more_b = theirs.next(b);
    if (more_a != more_b) {
      fail("message counts differ");
      break;
    }
    if (!more_a) break;
    if (a.channel->topic != b.channel->topic) fail("topic " + b.channel->topic);
    if (a.channel->message_encoding != b.channel->message_encoding) fail("message encoding");
    if (b.schema == nullptr || a.schema->name != b.schema->name) fail("schema name");
    if (a.log_time_ns != b.log_time_ns || a.publish_time_ns != b.publish_time_ns) fail("times");
    if (a.sequence != b.sequence) fail("sequence");
    identical_bytes += std::equal(a.data.begin(), a.data.end(), b.data.begin(), b.data.end());
    try {
      std::optional<bool> same;
      if (!same) same = same_as<ros_msgs::Image>(a, b);
      if (!same) same = same_as<ros_msgs::Imu>(a, b);
      if (!same) same = same_as<ros_msgs::CameraInfo>(a, b);
      if (!same) same = same_as<ros_msgs::PoseStamped>(a, b);
      if (!same) same = same_as<ros_msgs::Odometry>(a, b);
      if (!same) same = same_as<ros_msgs::SerialChunk>(a, b);
      if (!same) fail("unknown type " + a.schema->name);
      if (same && !*same) fail(a.schema->name + " decodes to different values");
    } catch (const ros_msgs::DecodeError& e) {
      fail(e.what());
    }
  }
  for (const auto* r : {&ours, &theirs}) {
    for (const auto& issue : r->issues()) fail(issue.message);
  }
  if (!theirs.has_summary()) fail(std::string(theirs_path) + ": no summary read");
  if (bad > 0) return 1;
  std::printf(
      "%s: %d messages written by @mcap/core read back equal (%d byte-identical payloads)\n",
      theirs_path, n, identical_bytes);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::string(argv[1]) == "compare") return compare(argv[2], argv[3]);
  const bool ascii_only = argc == 5 && std::string(argv[4]) == "--ascii";
  if (argc != 4 && !ascii_only) {
    std::fprintf(stderr,
                 "usage: %s cdr|ros1 OUT.mcap OUT.json [--ascii]\n"
                 "       %s compare OURS.mcap THEIRS.mcap\n",
                 argv[0], argv[0]);
    return 2;
  }
  const Encoding e = std::string(argv[1]) == "ros1" ? Encoding::kRos1 : Encoding::kCdr;
  mcap::McapWriterOptions options;
  options.chunk_size_bytes = 2000;  // several chunks
  options.profile = e == Encoding::kCdr ? "ros2" : "ros1";
  mcap::McapWriter w(argv[2], options);
  std::ostringstream json;
  json << "{\"messages\":[";
  std::vector<std::uint8_t> buf;
  std::uint64_t t = 1'700'000'000'000'000'000ull;
  std::uint32_t seq[8] = {};
  bool first = true;
  auto put = [&](std::uint16_t ch, const std::string& topic, const auto& msg) {
    using M = std::decay_t<decltype(msg)>;
    ros_msgs::write_message(w, ch, t, msg, buf, e);
    json << (first ? "" : ",") << "{\"topic\":" << str(topic) << ",\"log_time\":\"" << t
         << "\",\"publish_time\":\"" << t << "\",\"sequence\":" << seq[ch]++
         << ",\"schema\":" << str(std::string(ros_msgs::type_name<M>(e)))
         << ",\"message\":" << Json{e}(msg) << "}";
    first = false;
    t += 5'000'000;
  };
  const auto rgb = ros_msgs::add_channel<ros_msgs::Image>(w, "/tesse/left_cam/rgb/image_raw", e);
  const auto depth =
      ros_msgs::add_channel<ros_msgs::Image>(w, "/tesse/depth_cam/mono/image_raw", e);
  const auto imu = ros_msgs::add_channel<ros_msgs::Imu>(w, "/tesse/imu/clean/imu", e);
  const auto info =
      ros_msgs::add_channel<ros_msgs::CameraInfo>(w, "/tesse/left_cam/camera_info", e);
  const auto pose = ros_msgs::add_channel<ros_msgs::PoseStamped>(w, "/vigs/ground_truth", e);
  const auto odom = ros_msgs::add_channel<ros_msgs::Odometry>(w, "/tesse/odom", e);
  const auto serial = ros_msgs::add_channel<ros_msgs::SerialChunk>(w, "/vigs/serial_imu", e);
  for (int i = 0; i < 4; ++i) {
    put(rgb, "/tesse/left_cam/rgb/image_raw", test::sample_image(i, false));
    put(depth, "/tesse/depth_cam/mono/image_raw", test::sample_image(i, true));
    auto m = test::sample_imu(i);
    if (i == 1 && !ascii_only) m.header.frame_id = "imu_\xc3\xa4";  // UTF-8
    if (i == 2) m.linear_acceleration.x = 1e-300;
    put(imu, "/tesse/imu/clean/imu", m);
    auto c = test::sample_camera_info(i);
    if (i == 3) c.d.clear();
    put(info, "/tesse/left_cam/camera_info", c);
    put(pose, "/vigs/ground_truth", test::sample_pose(i));
    put(odom, "/tesse/odom", test::sample_odometry(i));
    put(serial, "/vigs/serial_imu", test::sample_serial(i));
  }
  w.close();
  json << "]}\n";
  std::ofstream out(argv[3]);
  out << json.str();
  return out ? 0 : 1;
}
