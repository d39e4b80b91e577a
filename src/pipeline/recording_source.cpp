#include "pipeline/recording_source.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "io/mcap/mcap_reader.hpp"
#include "io/recording/recorded_frames.hpp"
#include "io/recording_topics.hpp"
#include "pipeline/recorded_motion.hpp"
#include "rt/clock.hpp"

namespace vigs::pipeline {
namespace {

struct StopReading {};

/// Copies `view` into `frame` (pool layout: raw depth in units of depth_scale_m, rgb8).
void copy_into(const RgbdView& view, rt::Frame& frame, float depth_scale_m) {
  const int w = view.width_px, h = view.height_px;
  view.with_depth_m([&](auto depth_at) {
    std::size_t i = 0;
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        const float z = depth_at(u, v) / depth_scale_m;
        frame.depth[i++] = std::isfinite(z) && z > 0.0f && z < 65535.0f
                               ? static_cast<std::uint16_t>(std::lround(z))
                               : std::uint16_t{0};
      }
  });
  std::size_t i = 0;
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u)
      for (const std::uint8_t c : view.rgb_at(u, v)) frame.colour[i++] = c;
  frame.t_ns = view.t_ns;
}

}  // namespace

RecordingSource::RecordingSource(const RecordingSourceSettings& s, rt::FramePool& pool,
                                 rt::SpscRing<rt::FrameHandle>& frames,
                                 rt::SpscRing<ImuSample>& imu)
    : s_(s), pool_(pool), frames_(frames), imu_(imu) {
  camera_ = first_camera(s_.path, &first_t_ns_);
  const rt::FramePoolSettings& p = pool_.settings();
  if (static_cast<std::uint32_t>(camera_.width_px) != p.width ||
      static_cast<std::uint32_t>(camera_.height_px) != p.height || p.colour_channels != 3) {
    throw RecordingError(s_.path + ": frames are " + std::to_string(camera_.width_px) + "x" +
                         std::to_string(camera_.height_px) + ", the frame pool holds " +
                         std::to_string(p.width) + "x" + std::to_string(p.height) +
                         " (camera.width_px / height_px)");
  }
}

PinholeCamera RecordingSource::first_camera(const std::string& path, std::int64_t* first_t_ns) {
  std::optional<PinholeCamera> camera;
  try {
    io::for_each_recorded_frame(path, [&](const io::RecordedFrame& f) {
      camera = f.camera;
      if (first_t_ns != nullptr) *first_t_ns = f.view.t_ns;
      throw StopReading{};
    });
  } catch (const StopReading&) {
  }
  if (!camera) throw RecordingError(path + ": no RGB-D frames");
  return *camera;
}

std::uint64_t RecordingSource::frame_count(const std::string& path) {
  const std::string topic(io::topics::kRgb.name);
  io::mcap::McapReaderOptions options;
  options.topics = {topic};
  io::mcap::McapReader reader(path, options);
  // The summary's count when it has one for the colour channel; a summary without the channel's
  // record (the spec allows it) or its count is no answer: then the messages are counted.
  if (const auto& st = reader.statistics()) {
    if (const io::mcap::Channel* channel = reader.find_channel(topic)) {
      const auto it = st->channel_message_counts.find(channel->id);
      if (it != st->channel_message_counts.end()) return it->second;
    }
  }
  std::uint64_t n = 0;
  io::mcap::MessageView m;
  while (reader.next(m)) ++n;
  return n;
}

RecordingSource::~RecordingSource() {
  stop();
}

void RecordingSource::start() {
  thread_.emplace(s_.thread, [this](std::stop_token st) {
    try {
      run(st);
    } catch (const std::exception& e) {
      error_ = e.what();
    }
    // End marker: never dropped (retried until the consumer makes room or stop()).
    while (!st.stop_requested() && !frames_.try_push(rt::FrameHandle{}))
      rt::sleep_until_ns(rt::monotonic_ns() + 1'000'000);
    ended_.store(true, std::memory_order_release);
  });
}

void RecordingSource::stop() {
  if (!thread_) return;
  thread_->request_stop();
  thread_->join();
  thread_.reset();
}

template <class Pred>
bool RecordingSource::push(const std::stop_token& stop, Pred&& try_once, const char* what) {
  if (try_once()) return true;
  if (!s_.lockstep) return false;
  const std::int64_t give_up = rt::monotonic_ns() + s_.wait_timeout_ns;
  while (!try_once()) {
    if (stop.stop_requested()) return false;
    if (rt::monotonic_ns() > give_up)
      throw std::runtime_error(std::string("lockstep: the source waited ") +
                               std::to_string(rt::ns_to_s(s_.wait_timeout_ns)) + " s for " + what +
                               " (the tracker consumed nothing)");
    rt::sleep_until_ns(rt::monotonic_ns() + 100'000);
  }
  return true;
}

void RecordingSource::run(const std::stop_token& stop) {
  const RecordedMotion motion = read_recorded_motion(s_.path);
  std::size_t next_imu = 0;
  std::int64_t frames = 0;
  const auto pace = [&](std::int64_t t_ns) {
    if (s_.lockstep) return;
    rt::sleep_until_ns(start_mono_ns_.load() + (t_ns - first_t_ns_));
  };
  start_mono_ns_.store(rt::monotonic_ns());
  const auto on_frame = [&](const io::RecordedFrame& rec) {
    if (stop.stop_requested() || (s_.max_frames > 0 && frames >= s_.max_frames))
      throw StopReading{};
    const std::int64_t t_ns = rec.view.t_ns;
    for (; next_imu < motion.imu.size() && motion.imu[next_imu].t_ns <= t_ns; ++next_imu) {
      const ImuSample& s = motion.imu[next_imu];
      pace(s.t_ns);
      if (push(
              stop, [&] { return imu_.try_push(s); }, "the imu ring"))
        imu_out_.add();
      else
        imu_drops_.add();
    }
    pace(t_ns);
    if (rec.view.width_px != camera_.width_px || rec.view.height_px != camera_.height_px)
      throw RecordingError(s_.path + ": frame " + std::to_string(rec.index) + " changes size");
    rt::FrameHandle h;
    if (!push(
            stop, [&] { return (h = pool_.acquire()).valid(); }, "a free frame pool slot")) {
      frame_drops_.add();
      ++frames;
      return;
    }
    copy_into(rec.view, pool_.frame(h), s_.depth_scale_m);
    pool_.frame(h).sequence = rec.index;
    pool_.frame(h).arrival_ns = rt::monotonic_ns();
    if (push(
            stop, [&] { return frames_.try_push(h); }, "the frame ring")) {
      frames_out_.add();
    } else {
      pool_.release(h);
      frame_drops_.add();
    }
    ++frames;
  };
  try {
    io::for_each_recorded_frame(s_.path, on_frame);
  } catch (const StopReading&) {
  }
}

RecordingSourceCounters RecordingSource::counters() const noexcept {
  return {frames_out_.get(), imu_out_.get(), frame_drops_.get(), imu_drops_.get()};
}

}  // namespace vigs::pipeline
