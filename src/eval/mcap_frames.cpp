#include "eval/mcap_frames.hpp"

#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>

#include "io/io_error.hpp"
#include "io/mcap/damage_report.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/message_checks.hpp"
#include "io/ros_msgs/typed_io.hpp"

namespace vigs::eval {
namespace {

/// Gives the pending frame its depth when stamp and size match and the encoding is known.
/// A depth image of the frame's stamp and size whose step or data do not hold it is an error.
void attach_depth(const io::ros_msgs::Image& img, bool pending, RecordedFrame& f,
                  const std::string& where) {
  if (!pending) return;
  if (static_cast<double>(img.header.stamp.to_ns()) * 1e-9 != f.t_s) return;
  if (img.width != static_cast<std::uint32_t>(f.rgb.width) ||
      img.height != static_cast<std::uint32_t>(f.rgb.height) || img.is_bigendian)
    return;
  const int w = f.rgb.width, h = f.rgb.height;
  const int bytes = img.encoding == "16UC1" ? 2 : img.encoding == "32FC1" ? 4 : 0;
  if (bytes == 0) return;
  io::ros_msgs::check_image(where, img, static_cast<std::uint64_t>(bytes));
  f.depth_m = io::ImageF32(w, h, 1);
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* row = img.data.data() + static_cast<std::size_t>(y) * img.step;
    for (int x = 0; x < w; ++x) {
      float z = 0;
      if (bytes == 2) {
        z = static_cast<float>(row[2 * x] | (row[2 * x + 1] << 8)) * 1e-3f;
      } else {
        std::memcpy(&z, row + 4 * x, 4);
      }
      f.depth_m.at(x, y) = std::isfinite(z) && z > 0 ? z : 0.0f;
    }
  }
}

}  // namespace

McapFrameStats for_each_recorded_frame(const std::string& path,
                                       const std::function<void(const RecordedFrame&)>& fn,
                                       const std::string& rgb_topic, const std::string& info_topic,
                                       const std::string& depth_topic) {
  McapFrameStats st;
  io::mcap::McapReaderOptions opt;
  opt.topics = {rgb_topic, info_topic, depth_topic};
  io::mcap::McapReader reader(path, opt);
  io::mcap::MessageView m;
  io::ros_msgs::CameraInfo info;
  io::ros_msgs::Image img;
  std::optional<PinholeCamera> camera;
  RecordedFrame f;
  bool pending = false;  // f waits for its depth image
  const auto flush = [&] {
    if (!pending) return;
    pending = false;
    ++st.frames;
    fn(f);
  };
  std::uint64_t index = 0;
  const auto record = [&] {
    return path + ": " + m.channel->topic + " message at byte " + std::to_string(m.record_offset);
  };
  const auto where = [&](const std::string& what) {
    return std::runtime_error(record() + ": " + what);
  };
  while (reader.next(m)) {
    try {
      if (m.channel->topic == info_topic) {
        if (!io::ros_msgs::decode_message(m, info)) throw where("not sensor_msgs/CameraInfo");
        io::ros_msgs::check_camera_info(record(), info);
        camera = PinholeCamera{static_cast<int>(info.width),
                               static_cast<int>(info.height),
                               info.k[0],
                               info.k[4],
                               info.k[2],
                               info.k[5]};
        continue;
      }
      if (!io::ros_msgs::decode_message(m, img)) throw where("not sensor_msgs/Image");
      if (m.channel->topic == depth_topic) {
        attach_depth(img, pending, f, record());
        flush();
        continue;
      }
    } catch (const io::ros_msgs::DecodeError& e) {
      throw where(e.what());
    }
    flush();
    const std::uint64_t i = index++;
    if (!camera) {
      ++st.without_camera_info;
      continue;
    }
    const int ch = img.encoding == "mono8"                              ? 1
                   : (img.encoding == "rgb8" || img.encoding == "bgr8") ? 3
                                                                        : 0;
    if (ch == 0)
      throw where("colour encoding '" + img.encoding + "' (rgb8, bgr8 or mono8 expected)");
    if (img.width != static_cast<std::uint32_t>(camera->width_px) ||
        img.height != static_cast<std::uint32_t>(camera->height_px))
      throw where("image is " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                  " but its CameraInfo says " + std::to_string(camera->width_px) + "x" +
                  std::to_string(camera->height_px));
    // 64-bit checks of width x channels, step x height against the data (the CameraInfo sizes
    // are range-checked already).
    io::ros_msgs::check_image(record(), img, static_cast<std::uint64_t>(ch));
    const int w = camera->width_px, h = camera->height_px;
    f.index = i;
    f.t_s = static_cast<double>(img.header.stamp.to_ns()) * 1e-9;
    f.camera = *camera;
    f.rgb = io::ImageU8(w, h, 3);
    for (int y = 0; y < h; ++y) {
      const std::uint8_t* row = img.data.data() + static_cast<std::size_t>(y) * img.step;
      for (int x = 0; x < w; ++x) {
        for (int c = 0; c < 3; ++c) {
          const int src = ch == 1 ? 0 : (img.encoding == "bgr8" ? 2 - c : c);
          f.rgb.at(x, y, c) = row[x * ch + src];
        }
      }
    }
    f.depth_m = io::ImageF32();
    pending = true;
  }
  flush();
  st.damage = io::mcap::damage_of(reader);
  return st;
}

}  // namespace vigs::eval
