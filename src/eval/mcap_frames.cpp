#include "eval/mcap_frames.hpp"

#include <optional>
#include <stdexcept>

#include "io/io_error.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/typed_io.hpp"

namespace vigs::eval {

McapFrameStats for_each_recorded_frame(const std::string& path,
                                       const std::function<void(const RecordedFrame&)>& fn,
                                       const std::string& rgb_topic,
                                       const std::string& info_topic) {
  McapFrameStats st;
  io::mcap::McapReaderOptions opt;
  opt.topics = {rgb_topic, info_topic};
  io::mcap::McapReader reader(path, opt);
  io::mcap::MessageView m;
  io::ros_msgs::CameraInfo info;
  io::ros_msgs::Image img;
  std::optional<PinholeCamera> camera;
  RecordedFrame f;
  std::uint64_t index = 0;
  const auto where = [&](const std::string& what) {
    return std::runtime_error(path + ": " + m.channel->topic + " message at byte " +
                              std::to_string(m.record_offset) + ": " + what);
  };
  while (reader.next(m)) {
    try {
      if (m.channel->topic == info_topic) {
        if (!io::ros_msgs::decode_message(m, info)) throw where("not sensor_msgs/CameraInfo");
        camera = PinholeCamera{static_cast<int>(info.width),
                               static_cast<int>(info.height),
                               info.k[0],
                               info.k[4],
                               info.k[2],
                               info.k[5]};
        continue;
      }
      if (!io::ros_msgs::decode_message(m, img)) throw where("not sensor_msgs/Image");
    } catch (const io::ros_msgs::DecodeError& e) {
      throw where(e.what());
    }
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
    const int w = static_cast<int>(img.width), h = static_cast<int>(img.height);
    if (w != camera->width_px || h != camera->height_px)
      throw where("image is " + std::to_string(w) + "x" + std::to_string(h) +
                  " but its CameraInfo says " + std::to_string(camera->width_px) + "x" +
                  std::to_string(camera->height_px));
    if (img.step < static_cast<std::uint32_t>(w * ch) ||
        img.data.size() < static_cast<std::size_t>(img.step) * static_cast<std::size_t>(h))
      throw where("image data shorter than step x height");
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
    ++st.frames;
    fn(f);
  }
  return st;
}

}  // namespace vigs::eval
