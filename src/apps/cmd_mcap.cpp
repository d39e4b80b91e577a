// `vigs mcap info FILE [--decode] [--topic T]...`: reads a recording front to back and prints
// JSON: header, summary statistics, per-channel counts and time range, and every problem found
// (truncation, corruption, CRC mismatches) with its byte offset. With --decode every message of
// a known ROS type is decoded too. Exit 0 = clean, 1 = problems found, 2 = cannot open.
// `vigs mcap oni IN.mcap OUT.oni [...]`: colour + depth images to an OpenNI2 `.oni` clip.
#include <cstdio>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "apps/commands.hpp"
#include "io/io_error.hpp"
#include "io/json_text.hpp"
#include "io/mcap/damage_object.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/oni/mcap_to_oni.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/odometry.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/serial_chunk.hpp"
#include "io/ros_msgs/typed_io.hpp"

namespace vigs::apps {
namespace {

struct ChannelStats {
  std::uint64_t messages = 0, first_ns = 0, last_ns = 0, decode_errors = 0;
  bool decodable = false;
  std::string first_error;
};

// Decodes a message of a known type; returns false if the type is not one of ours.
bool try_decode(const io::mcap::MessageView& m) {
  using namespace io::ros_msgs;
  Image image;
  Imu imu;
  CameraInfo info;
  PoseStamped pose;
  Odometry odom;
  SerialChunk serial;
  return decode_message(m, image) || decode_message(m, imu) || decode_message(m, info) ||
         decode_message(m, pose) || decode_message(m, odom) || decode_message(m, serial);
}

int run_info(const std::string& file, bool decode, const std::vector<std::string>& topics) {
  io::mcap::McapReaderOptions options;
  options.topics.insert(topics.begin(), topics.end());
  std::unique_ptr<io::mcap::McapReader> reader;
  try {
    reader = std::make_unique<io::mcap::McapReader>(file, options);
  } catch (const io::IoError& e) {
    std::cerr << e.what() << "\n";
    return 2;
  }
  std::map<std::uint16_t, ChannelStats> stats;
  std::uint64_t total = 0, decode_errors = 0;
  io::mcap::MessageView m;
  while (reader->next(m)) {
    ChannelStats& s = stats[m.channel->id];
    if (s.messages == 0) s.first_ns = m.log_time_ns;
    s.last_ns = m.log_time_ns;
    ++s.messages;
    ++total;
    if (!decode) continue;
    try {
      s.decodable = try_decode(m) || s.decodable;
    } catch (const io::ros_msgs::DecodeError& e) {
      s.decodable = true;
      if (s.decode_errors++ == 0) s.first_error = e.what();
      ++decode_errors;
    }
  }
  io::Json j;
  j["file"] = file;
  j["profile"] = reader->profile();
  j["library"] = reader->library();
  j["summary"] = reader->has_summary();
  j["messages"] = total;
  if (const auto& st = reader->statistics()) {
    j["statistics"] = {{"message_count", st->message_count},
                       {"chunk_count", st->chunk_count},
                       {"message_start_time_ns", st->message_start_time_ns},
                       {"message_end_time_ns", st->message_end_time_ns}};
  }
  io::Json& channels = j["channels"] = io::Json::array();
  for (const io::mcap::Channel* c : reader->channels()) {
    if (!options.topics.empty() && !options.topics.contains(c->topic)) continue;
    const ChannelStats& s = stats[c->id];
    const io::mcap::Schema* schema = nullptr;
    for (const io::mcap::Schema* sc : reader->schemas()) {
      if (sc->id == c->schema_id) schema = sc;
    }
    io::Json ch;
    ch["id"] = c->id;
    ch["topic"] = c->topic;
    ch["schema"] = schema ? schema->name : std::string();
    ch["message_encoding"] = c->message_encoding;
    ch["messages"] = s.messages;
    ch["first_log_time_ns"] = s.first_ns;
    ch["last_log_time_ns"] = s.last_ns;
    if (decode) {
      ch["decoded"] = s.decodable;
      ch["decode_errors"] = s.decode_errors;
      if (s.decode_errors > 0) ch["first_decode_error"] = s.first_error;
    }
    channels.push_back(std::move(ch));
  }
  io::Json& issues = j["issues"] = io::Json::array();
  for (const auto& issue : reader->issues()) {
    issues.push_back({{"kind", std::string(to_string(issue.kind))},
                      {"offset", issue.offset},
                      {"message", issue.message}});
  }
  std::cout << io::json_lines(j) << "\n";
  return reader->issues().empty() && decode_errors == 0 ? 0 : 1;
}

}  // namespace

void add_mcap_command(CLI::App& app, ExitCode& exit_code) {
  auto* mcap = app.add_subcommand("mcap", "Inspect MCAP recordings");
  mcap->require_subcommand(1);
  auto* info = mcap->add_subcommand(
      "info",
      "Read a recording front to back; print channels, counts and problems (byte offsets) as JSON");
  static std::string file;
  static bool decode = false;
  static std::vector<std::string> topics;
  info->add_option("FILE", file, "MCAP file")->required();
  info->add_flag("--decode", decode,
                 "also decode every message of a known type (Image, Imu, CameraInfo, "
                 "PoseStamped, Odometry, SerialChunk; cdr or ros1)");
  info->add_option("--topic", topics, "only these topics (repeatable)");
  info->callback([&exit_code] { exit_code.value = run_info(file, decode, topics); });

  auto* oni = mcap->add_subcommand(
      "oni", "Write the colour and depth images of a recording as an OpenNI2 .oni clip (JSON out)");
  static std::string in, out;
  static io::oni::McapToOniOptions oni_options;
  oni->add_option("IN", in, "MCAP file")->required();
  oni->add_option("OUT", out, "ONI file to write (atomically)")->required();
  oni->add_option("--rgb-topic", oni_options.rgb_topic, "rgb8, bgr8 or mono8 Image topic")
      ->capture_default_str();
  oni->add_option("--depth-topic", oni_options.depth_topic, "16UC1 (mm) or 32FC1 (m) Image topic")
      ->capture_default_str();
  oni->add_option("--max-frames", oni_options.max_frames, "at most this many frames")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  oni->add_option("--fps", oni_options.fps, "clip fps (0 = from the stamps)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000));
  oni->callback([&exit_code] {
    try {
      const auto r = io::oni::make_oni_from_mcap(in, out, oni_options);
      const std::string used = std::to_string(r.frames) + " frame pairs up to stamp " +
                               std::to_string(r.last_stamp_ns) + " ns";
      if (r.damage.damaged())
        std::cerr << "vigs mcap oni: " << io::mcap::damage_warning(r.damage, used) << "\n";
      std::cout << io::json_line({{"oni", out},
                                  {"frames", r.frames},
                                  {"unmatched", r.unmatched},
                                  {"fps", io::rounded(r.fps, 6)},
                                  {"width", r.width},
                                  {"height", r.height},
                                  {"input_damage", io::mcap::damage_object(r.damage, used)}})
                << "\n";
    } catch (const io::IoError& e) {
      std::cerr << e.what() << "\n";
      exit_code.value = 1;
    }
  });
}

}  // namespace vigs::apps
