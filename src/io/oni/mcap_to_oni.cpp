#include "io/oni/mcap_to_oni.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <vector>

#include "io/io_error.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/oni/oni_clip_writer.hpp"
#include "io/output_guard.hpp"
#include "io/ros_msgs/image_view.hpp"
#include "io/ros_msgs/typed_io.hpp"

namespace vigs::io::oni {
namespace {

struct Frame {
  std::vector<std::uint8_t> rgb;
  std::vector<std::uint16_t> depth_mm;
  bool has_rgb = false, has_depth = false;
};

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw IoError("MCAP to ONI: " + path + ": " + what);
}

std::vector<std::uint8_t> to_rgb(const ros_msgs::ImageView& img, const std::string& path) {
  const bool mono = img.encoding == "mono8";
  const bool bgr = img.encoding == "bgr8";  // compared once, not per pixel
  const std::size_t bpp = mono ? 1 : 3;
  if (!mono && img.encoding != "rgb8" && img.encoding != "bgr8") {
    fail(path, "colour encoding '" + img.encoding + "' (expected rgb8, bgr8 or mono8)");
  }
  if (std::size_t{img.step} < img.width * bpp ||
      img.data.size() < std::size_t{img.step} * img.height) {
    fail(path, "colour image data shorter than step x height");
  }
  std::vector<std::uint8_t> rgb(std::size_t{img.width} * img.height * 3);
  for (std::uint32_t y = 0; y < img.height; ++y) {
    const std::uint8_t* row = img.data.data() + std::size_t{y} * img.step;
    for (std::uint32_t x = 0; x < img.width; ++x) {
      std::uint8_t* out = &rgb[(std::size_t{y} * img.width + x) * 3];
      if (mono) {
        out[0] = out[1] = out[2] = row[x];
      } else if (bgr) {
        out[0] = row[3 * x + 2];
        out[1] = row[3 * x + 1];
        out[2] = row[3 * x];
      } else {
        std::memcpy(out, row + 3 * x, 3);
      }
    }
  }
  return rgb;
}

std::vector<std::uint16_t> to_depth_mm(const ros_msgs::ImageView& img, const std::string& path) {
  const bool mm = img.encoding == "16UC1" || img.encoding == "mono16";
  const bool metres = img.encoding == "32FC1";
  if (!mm && !metres) {
    fail(path, "depth encoding '" + img.encoding + "' (expected 16UC1 in mm or 32FC1 in m)");
  }
  if (img.is_bigendian != 0) fail(path, "big-endian depth images are not supported");
  const std::size_t bpp = mm ? 2 : 4;
  if (std::size_t{img.step} < img.width * bpp ||
      img.data.size() < std::size_t{img.step} * img.height) {
    fail(path, "depth image data shorter than step x height");
  }
  std::vector<std::uint16_t> depth(std::size_t{img.width} * img.height);
  for (std::uint32_t y = 0; y < img.height; ++y) {
    const std::uint8_t* row = img.data.data() + std::size_t{y} * img.step;
    for (std::uint32_t x = 0; x < img.width; ++x) {
      std::uint16_t& out = depth[std::size_t{y} * img.width + x];
      if (mm) {
        std::memcpy(&out, row + 2 * x, 2);
      } else {
        float d_m = 0;
        std::memcpy(&d_m, row + 4 * x, 4);
        const double d_mm = std::round(static_cast<double>(d_m) * 1000.0);
        out =
            std::isfinite(d_mm) && d_mm > 0 && d_mm <= 65535 ? static_cast<std::uint16_t>(d_mm) : 0;
      }
    }
  }
  return depth;
}

}  // namespace

namespace {

// The messages read (in file order) and the colour/depth pairs among them, from a first pass
// that reads stamps and checks sizes from the images' leading fields only (ImageMeta): no
// pixel byte is copied or checked, that is the second pass's work.
struct PairPlan {
  std::size_t messages = 0;          // messages of the two topics read, the last one included
  std::vector<std::int64_t> stamps;  // complete pairs, ascending
  std::size_t unmatched = 0;
  std::uint32_t width = 0, height = 0;
};

PairPlan plan_pairs(const std::string& mcap_path, const McapToOniOptions& options) {
  mcap::McapReaderOptions ro;
  ro.topics = {options.rgb_topic, options.depth_topic};
  mcap::McapReader reader(mcap_path, ro);
  std::map<std::int64_t, std::uint8_t> halves;  // by header stamp: bit 0 colour, bit 1 depth
  PairPlan plan;
  mcap::MessageView m;
  ros_msgs::ImageMeta img;
  std::size_t complete = 0;
  while (complete < options.max_frames && reader.next(m)) {
    ++plan.messages;
    try {
      if (!ros_msgs::decode_message(m, img)) fail(mcap_path, m.channel->topic + " is not an Image");
    } catch (const ros_msgs::DecodeError& e) {
      fail(mcap_path, e.what());
    }
    if (img.width == 0 || img.height == 0 ||
        std::uint64_t{img.width} * img.height > 1600ull * 1200ull) {
      fail(mcap_path, "image of " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                          " on " + m.channel->topic + " (ONI clips hold at most 1600x1200)");
    }
    if (plan.width == 0) {
      plan.width = img.width;
      plan.height = img.height;
    }
    if (img.width != plan.width || img.height != plan.height) {
      fail(mcap_path, "image sizes differ (" + std::to_string(img.width) + "x" +
                          std::to_string(img.height) + " on " + m.channel->topic + ")");
    }
    const std::int64_t t_ns = img.header.stamp.to_ns();
    if (t_ns < options.from_stamp_ns || t_ns > options.to_stamp_ns) continue;
    const std::uint8_t bit = m.channel->topic == options.rgb_topic ? 1 : 2;
    std::uint8_t& h = halves[t_ns];
    if ((h & bit) != 0) continue;  // a second image of that half: ignored
    h |= bit;
    complete += h == 3;
  }
  for (const auto& [t, h] : halves) {
    if (h == 3) {
      plan.stamps.push_back(t);
    } else {
      ++plan.unmatched;
    }
  }
  return plan;
}

}  // namespace

McapToOniResult make_oni_from_mcap(const std::string& mcap_path, const std::string& oni_path,
                                   const McapToOniOptions& options) {
  refuse_output_over_inputs(oni_path, {mcap_path});
  // Two passes, so that memory stays at a few frames whatever the recording's length (a
  // 3-minute 720x480 clip is 6 GB): the first finds the pairs and the frame rate, the second
  // converts each pair as it completes and writes it in stamp order.
  const PairPlan plan = plan_pairs(mcap_path, options);
  if (plan.stamps.empty()) {
    fail(mcap_path, "no colour/depth pairs with equal stamps on " + options.rgb_topic + " and " +
                        options.depth_topic);
  }
  McapToOniResult result;
  result.width = plan.width;
  result.height = plan.height;
  result.unmatched = plan.unmatched;
  result.fps = options.fps;
  if (result.fps == 0) {
    std::vector<std::int64_t> dt;
    for (std::size_t i = 1; i < plan.stamps.size(); ++i)
      dt.push_back(plan.stamps[i] - plan.stamps[i - 1]);
    std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
    result.fps =
        dt.empty() || dt[dt.size() / 2] <= 0
            ? 30
            : static_cast<std::uint32_t>(std::max(1.0, std::round(1e9 / dt[dt.size() / 2])));
  }

  mcap::McapReaderOptions ro;
  ro.topics = {options.rgb_topic, options.depth_topic};
  mcap::McapReader reader(mcap_path, ro);
  OniClipWriter writer(oni_path, {result.width, result.height, result.fps});
  std::map<std::int64_t, Frame> pending;  // pairs (or halves) not yet written, by stamp
  std::size_t next = 0;                   // plan.stamps[next] is the next pair to write
  mcap::MessageView m;
  ros_msgs::ImageMeta meta;
  ros_msgs::ImageView img;
  for (std::size_t k = 0; k < plan.messages && next < plan.stamps.size() && reader.next(m); ++k) {
    // The stamp first: the pixels of images that are not converted are not read.
    try {
      if (!ros_msgs::decode_message(m, meta))
        fail(mcap_path, m.channel->topic + " is not an Image");
    } catch (const ros_msgs::DecodeError& e) {
      fail(mcap_path, m.channel->topic + ": " + e.what());
    }
    const std::int64_t t_ns = meta.header.stamp.to_ns();
    if (!std::binary_search(plan.stamps.begin() + static_cast<long>(next), plan.stamps.end(), t_ns))
      continue;  // not a pair (or written already)
    try {
      ros_msgs::decode_message(m, img);
    } catch (const ros_msgs::DecodeError& e) {
      fail(mcap_path,
           m.channel->topic + " image stamped " + std::to_string(t_ns) + " ns: " + e.what());
    }
    Frame& f = pending[t_ns];
    if (m.channel->topic == options.rgb_topic && !f.has_rgb) {
      f.rgb = to_rgb(img, mcap_path);
      f.has_rgb = true;
    } else if (m.channel->topic == options.depth_topic && !f.has_depth) {
      f.depth_mm = to_depth_mm(img, mcap_path);
      f.has_depth = true;
    }
    // Write every pair that is complete and next in stamp order.
    for (auto it = pending.begin();
         next < plan.stamps.size() && it != pending.end() && it->first == plan.stamps[next] &&
         it->second.has_rgb && it->second.has_depth;
         it = pending.erase(it), ++next) {
      if (options.recorded_stamps) {
        writer.add_frame_at(recorded_timestamp_us(it->first, plan.stamps.front()),
                            it->second.depth_mm, it->second.rgb);
      } else {
        writer.add_frame(it->second.depth_mm, it->second.rgb);
      }
    }
  }
  if (next != plan.stamps.size()) {
    fail(mcap_path, "the recording changed while it was converted (" + std::to_string(next) +
                        " of " + std::to_string(plan.stamps.size()) + " pairs found again)");
  }
  writer.close();
  result.frames = plan.stamps.size();
  result.first_stamp_ns = static_cast<std::uint64_t>(plan.stamps.front());
  result.last_stamp_ns = static_cast<std::uint64_t>(plan.stamps.back());
  result.damage = mcap::damage_of(reader);
  return result;
}

}  // namespace vigs::io::oni
