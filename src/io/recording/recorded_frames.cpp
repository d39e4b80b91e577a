#include "io/recording/recorded_frames.hpp"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include "io/io_error.hpp"
#include "io/mcap/damage_report.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/message_checks.hpp"
#include "io/ros_msgs/typed_io.hpp"

namespace vigs::io {
namespace {

/// The reader's reusable pixel buffers: after the first frame no per-frame allocation.
struct FrameBuffers {
  std::vector<std::uint8_t> rgb;  // bgr8 converted to rgb8
  std::vector<std::uint16_t> depth_u16;
  std::vector<float> depth_f32;
  std::vector<std::uint8_t> mask;  // the dynamic mask without row padding
};

/// Gives the pending frame its depth when stamp and size match and the encoding is known.
/// A depth image of the frame's stamp and size whose step or data do not hold it is an error.
void attach_depth(const io::ros_msgs::Image& img, bool pending, std::int64_t tolerance_ns,
                  FrameBuffers& buf, RecordedFrame& f, const std::string& where) {
  if (!pending) return;
  const std::int64_t dt_ns = img.header.stamp.to_ns() - f.view.t_ns;
  if (dt_ns > tolerance_ns || dt_ns < -tolerance_ns) return;
  if (img.width != static_cast<std::uint32_t>(f.view.width_px) ||
      img.height != static_cast<std::uint32_t>(f.view.height_px) || img.is_bigendian)
    return;
  const int w = f.view.width_px, h = f.view.height_px;
  const int bytes = img.encoding == "16UC1" ? 2 : img.encoding == "32FC1" ? 4 : 0;
  if (bytes == 0) return;
  io::ros_msgs::check_image(where, img, static_cast<std::uint64_t>(bytes));
  const auto n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  if (bytes == 2) {
    buf.depth_u16.resize(n);
  } else {
    buf.depth_f32.resize(n);
  }
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* row = img.data.data() + static_cast<std::size_t>(y) * img.step;
    const std::size_t at = static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    if (bytes == 2) {
      for (int x = 0; x < w; ++x)
        buf.depth_u16[at + static_cast<std::size_t>(x)] =
            static_cast<std::uint16_t>(row[2 * x] | (row[2 * x + 1] << 8));
    } else {
      float* out = buf.depth_f32.data() + at;
      std::memcpy(out, row, static_cast<std::size_t>(w) * 4);
      // NaN, Inf and negative depths (hostile or invalid pixels) become 0 = no depth.
      for (int x = 0; x < w; ++x)
        if (!(std::isfinite(out[x]) && out[x] > 0)) out[x] = 0.0f;
    }
  }
  f.view.depth_row_stride = static_cast<std::size_t>(w);
  if (bytes == 2) {
    f.view.depth_encoding = DepthEncoding::u16_scaled;
    f.view.depth_u16 = buf.depth_u16.data();
    f.view.depth_scale_m = 1e-3f;  // 16UC1: millimetres (REP 118)
  } else {
    f.view.depth_encoding = DepthEncoding::f32_metres;
    f.view.depth_f32_m = buf.depth_f32.data();
  }
}

/// Gives the pending frame the mask of its stamp (exactly: the simulator writes both with one
/// stamp); masks of other stamps are ignored. Returns whether it was attached. A mask of the
/// frame's stamp that is not mono8 of the frame's size is an error.
bool attach_mask(const io::ros_msgs::Image& img, bool pending, FrameBuffers& buf, RecordedFrame& f,
                 const std::string& where) {
  if (!pending || img.header.stamp.to_ns() != f.view.t_ns) return false;
  const int w = f.view.width_px, h = f.view.height_px;
  if (img.encoding != "mono8" || img.width != static_cast<std::uint32_t>(w) ||
      img.height != static_cast<std::uint32_t>(h))
    throw std::runtime_error(where + ": mask is " + std::to_string(img.width) + "x" +
                             std::to_string(img.height) + " '" + img.encoding +
                             "' but its frame is " + std::to_string(w) + "x" + std::to_string(h) +
                             " (mono8 expected)");
  io::ros_msgs::check_image(where, img, 1);
  buf.mask.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  for (int y = 0; y < h; ++y)
    std::memcpy(buf.mask.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(w),
                img.data.data() + static_cast<std::size_t>(y) * img.step,
                static_cast<std::size_t>(w));
  f.dynamic_mask = buf.mask.data();
  return true;
}

}  // namespace

McapFrameStats for_each_recorded_frame(const std::string& path,
                                       const std::function<void(const RecordedFrame&)>& fn,
                                       const std::string& rgb_topic, const std::string& info_topic,
                                       const std::string& depth_topic,
                                       std::int64_t depth_tolerance_ns,
                                       const std::string& mask_topic) {
  McapFrameStats st;
  io::mcap::McapReaderOptions opt;
  opt.topics = {rgb_topic, info_topic, depth_topic};
  const bool want_mask = !mask_topic.empty();
  if (want_mask) opt.topics.insert(mask_topic);
  io::mcap::McapReader reader(path, opt);
  io::mcap::MessageView m;
  io::ros_msgs::CameraInfo info;
  io::ros_msgs::Image img;     // the message being decoded
  io::ros_msgs::Image colour;  // the pending frame's colour message, viewed in place
  FrameBuffers buf;
  std::optional<PinholeCamera> camera;
  RecordedFrame f;
  bool pending = false;                        // f waits for its depth image (and mask)
  bool depth_seen = false, mask_seen = false;  // of the pending frame
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
        attach_depth(img, pending, depth_tolerance_ns, buf, f, record());
        depth_seen = true;
        if (!want_mask || mask_seen) flush();
        continue;
      }
      if (want_mask && m.channel->topic == mask_topic) {
        mask_seen = mask_seen || attach_mask(img, pending, buf, f, record());
        if (mask_seen && depth_seen) flush();
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
    std::swap(colour, img);  // keeps the pixels while the depth message is decoded into img
    f.index = i;
    f.camera = *camera;
    f.view = RgbdView{};
    f.dynamic_mask = nullptr;
    depth_seen = mask_seen = false;
    f.view.t_ns = colour.header.stamp.to_ns();
    f.view.width_px = w;
    f.view.height_px = h;
    if (colour.encoding == "bgr8") {
      buf.rgb.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3);
      for (int y = 0; y < h; ++y) {
        const std::uint8_t* row = colour.data.data() + static_cast<std::size_t>(y) * colour.step;
        std::uint8_t* out = buf.rgb.data() + static_cast<std::size_t>(y) * w * 3;
        for (int x = 0; x < 3 * w; x += 3) {
          out[x] = row[x + 2];
          out[x + 1] = row[x + 1];
          out[x + 2] = row[x];
        }
      }
      f.view.colour_encoding = ColourEncoding::rgb8;
      f.view.colour = buf.rgb.data();
      f.view.colour_row_stride = static_cast<std::size_t>(w) * 3;
    } else {
      f.view.colour_encoding = ch == 1 ? ColourEncoding::mono8 : ColourEncoding::rgb8;
      f.view.colour = colour.data.data();
      f.view.colour_row_stride = colour.step;
    }
    pending = true;
  }
  flush();
  st.damage = io::mcap::damage_of(reader);
  return st;
}

}  // namespace vigs::io
