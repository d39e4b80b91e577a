#include "pipeline/driver_replay.hpp"

#include <stdlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <system_error>

#include "drivers/openni2/openni2_driver.hpp"
#include "drivers/serial_imu/xsens_encoder.hpp"
#include "io/oni/mcap_to_oni.hpp"
#include "io/recording_topics.hpp"
#include "pipeline/recorded_motion.hpp"
#include "pipeline/recording_source.hpp"
#include "rt/clock.hpp"
#include "rt/poll.hpp"

namespace vigs::pipeline {
namespace {

namespace fs = std::filesystem;

constexpr std::int64_t kTickNs = 100'000;  // Xsens SampleTimeFine: 10 kHz
constexpr std::int64_t kLateNs = 1'000'000;
constexpr std::int64_t kWaitStepNs = 20'000'000;  // the feeder's sleeps: stop within this

io::oni::McapToOniOptions clip_options(std::int64_t max_frames) {
  io::oni::McapToOniOptions o;
  o.rgb_topic = std::string(io::topics::kRgb.name);
  o.depth_topic = std::string(io::topics::kDepth.name);
  o.recorded_stamps = true;
  o.max_frames = max_frames > 0 ? static_cast<std::size_t>(max_frames)
                                : std::numeric_limits<std::size_t>::max();
  return o;
}

std::string make_temp_dir() {
  std::string pattern = (fs::temp_directory_path() / "vigs-drivers-XXXXXX").string();
  if (::mkdtemp(pattern.data()) == nullptr)
    throw std::system_error(errno, std::generic_category(), "mkdtemp " + pattern);
  return pattern;
}

bool fresh(const fs::path& clip, const fs::path& recording) {
  std::error_code ec;
  const auto clip_time = fs::last_write_time(clip, ec);
  if (ec || fs::file_size(clip, ec) == 0 || ec) return false;
  const auto rec_time = fs::last_write_time(recording, ec);
  return !ec && clip_time >= rec_time;
}

}  // namespace

DriverReplay::DriverReplay(const DriverReplaySettings& settings) : s_(settings) {
  camera_ = RecordingSource::first_camera(s_.recording, &first_frame_t_ns_);
  imu_ = read_recorded_motion(s_.recording).imu;
  if (imu_.size() < 2) throw RecordingError(s_.recording + ": fewer than 2 IMU samples");
  std::vector<std::int64_t> dt;
  for (std::size_t i = 1; i < imu_.size(); ++i) dt.push_back(imu_[i].t_ns - imu_[i - 1].t_ns);
  std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
  if (dt[dt.size() / 2] > 0) imu_rate_hz_ = 1e9 / static_cast<double>(dt[dt.size() / 2]);
  make_clips();
}

std::string DriverReplay::cached_clip_path(const std::string& recording) {
  return fs::path(recording).replace_extension(".drivers.oni").string();
}

bool DriverReplay::clip_cached(const std::string& recording) {
  return fresh(cached_clip_path(recording), recording);
}

DriverReplay::~DriverReplay() {
  stop();
  if (!temp_dir_.empty()) {
    std::error_code ec;
    fs::remove_all(temp_dir_, ec);
  }
}

void DriverReplay::make_clips() {
  const DriverReplayFaults& f = s_.faults;
  if (!f.camera_gone() && s_.max_frames == 0) {
    // The whole recording's clip, cached next to it (or in a temp folder if that fails).
    fs::path cached = cached_clip_path(s_.recording);
    if (!fresh(cached, s_.recording)) {
      try {
        (void)io::oni::make_oni_from_mcap(s_.recording, cached.string(), clip_options(0));
      } catch (const std::exception&) {
        cached.clear();
      }
    }
    if (!cached.empty()) {
      clip_path_ = cached.string();
      return;
    }
  }
  temp_dir_ = make_temp_dir();
  clip_path_ = (fs::path(temp_dir_) / "camera.oni").string();
  io::oni::McapToOniOptions o = clip_options(s_.max_frames);
  if (!f.camera_gone()) {
    (void)io::oni::make_oni_from_mcap(s_.recording, clip_path_, o);
    return;
  }
  // The camera fault: the first clip ends inside the frame at camera_gone_at (OpenNI2's
  // playback stalls there, as a camera that stops sending), the second starts at the return.
  o.to_stamp_ns = first_frame_t_ns_ + f.camera_gone_at_ns;
  const io::oni::McapToOniResult gone = io::oni::make_oni_from_mcap(s_.recording, clip_path_, o);
  const std::uintmax_t bytes = fs::file_size(clip_path_);
  const std::uintmax_t colour_bytes = std::uintmax_t{gone.width} * gone.height * 3;
  fs::resize_file(clip_path_, bytes - colour_bytes / 2 - 64);  // inside the last colour image
  o.to_stamp_ns = INT64_MAX;
  o.from_stamp_ns = first_frame_t_ns_ + f.camera_gone_at_ns + f.camera_gone_ns;
  return_clip_path_ = (fs::path(temp_dir_) / "camera_back.oni").string();
  const io::oni::McapToOniResult back =
      io::oni::make_oni_from_mcap(s_.recording, return_clip_path_, o);
  return_t_ns_ = static_cast<std::int64_t>(back.first_stamp_ns);
}

void DriverReplay::start(const drivers::Openni2Driver& camera) {
  if (thread_) return;
  thread_.emplace(s_.feeder_thread, [this, &camera](std::stop_token st) { run(st, camera); });
}

void DriverReplay::stop() {
  if (!thread_) return;
  thread_->request_stop();
  thread_->join();
  thread_.reset();
}

void DriverReplay::finish(std::int64_t within_ns) {
  (void)rt::poll_until([this] { return !thread_ || done() || failed(); }, within_ns);
  stop();
}

std::optional<std::int64_t> DriverReplay::host_minus_recording_ns() const noexcept {
  const std::int64_t v = host_minus_recording_ns_.load(std::memory_order_acquire);
  return v == INT64_MIN ? std::nullopt : std::optional<std::int64_t>(v);
}

std::string DriverReplay::error() const {
  return failed_.load(std::memory_order_acquire) ? error_ : std::string();
}

DriverReplayCounters DriverReplay::counters() const noexcept {
  return {written_.get(), withheld_.get(), corrupted_.get(), late_.get(), returns_.get()};
}

void DriverReplay::run(const std::stop_token& stop, const drivers::Openni2Driver& camera) {
  const auto fail = [this](std::string what) {
    error_ = std::move(what);
    failed_.store(true, std::memory_order_release);
  };
  // 1. The camera leads: wait for its clock anchor (its first frame).
  const std::int64_t give_up = rt::monotonic_ns() + s_.anchor_timeout_ns;
  std::optional<std::int64_t> host_minus_device;
  while (!(host_minus_device = camera.host_minus_device_ns())) {
    if (stop.stop_requested()) return;
    if (rt::monotonic_ns() > give_up) {
      fail("through the drivers: the camera delivered no frame of " + clip_path_ + " within " +
           std::to_string(rt::ns_to_s(s_.anchor_timeout_ns)) + " s; no IMU was played");
      return;
    }
    rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(1));
  }
  // Clip device time of recording time t: 1 ms + (t - first frame) (io/oni/mcap_to_oni.hpp).
  const std::int64_t offset_ns =
      *host_minus_device + rt::ms_to_ns(1) - first_frame_t_ns_;  // host - recording
  host_minus_recording_ns_.store(offset_ns, std::memory_order_release);

  // 2. The IMU, paced by its stamps on that clock; the camera fault's return on the way.
  const DriverReplayFaults& f = s_.faults;
  const std::int64_t pause_from = first_frame_t_ns_ + f.imu_pause_at_ns;
  const std::int64_t pause_to = pause_from + f.imu_pause_ns;
  bool unplugged = return_clip_path_.empty(), returned = unplugged;
  const std::int64_t gone_t_ns = first_frame_t_ns_ + f.camera_gone_at_ns;
  std::uint64_t messages = 0;
  const std::int64_t t0 = imu_.front().t_ns;
  for (const ImuSample& s : imu_) {
    if (!unplugged && s.t_ns >= gone_t_ns) {
      // Unplugged: the open clip stalls where it was cut, and reopening finds no device.
      if (!rt::sleep_until_or_stop(gone_t_ns + offset_ns, stop, kWaitStepNs)) return;
      std::error_code ec;
      fs::remove(clip_path_, ec);
      unplugged = true;
    }
    if (!returned && s.t_ns >= return_t_ns_) {
      if (!rt::sleep_until_or_stop(return_t_ns_ + offset_ns, stop, kWaitStepNs)) return;
      std::error_code ec;
      fs::rename(return_clip_path_, clip_path_, ec);  // the camera is back
      if (ec)
        return fail("through the drivers: cannot put " + clip_path_ + " back: " + ec.message());
      returns_.add();
      returned = true;
    }
    const std::int64_t host_ns = s.t_ns + offset_ns;
    if (rt::monotonic_ns() > host_ns + kLateNs) late_.add();
    if (!rt::sleep_until_or_stop(host_ns, stop, kWaitStepNs)) return;
    if (f.imu_pause_at_ns >= 0 && s.t_ns >= pause_from && s.t_ns < pause_to) {
      withheld_.add();
      continue;
    }
    const auto stf =
        static_cast<std::uint32_t>(static_cast<std::uint64_t>((s.t_ns - t0) / kTickNs));
    std::vector<std::uint8_t> msg =
        drivers::xsens::encode_mtdata2(stf, {s.accel_mps2[0], s.accel_mps2[1], s.accel_mps2[2]},
                                       {s.gyro_rps[0], s.gyro_rps[1], s.gyro_rps[2]});
    if (f.corrupt_every > 0 && s.t_ns - first_frame_t_ns_ >= f.corrupt_from_ns &&
        ++messages % static_cast<std::uint64_t>(f.corrupt_every) == 0) {
      msg[msg.size() / 2] ^= 0x5A;  // inside the payload: the checksum no longer matches
      corrupted_.add();
    }
    if (!pty_.write_all(msg))
      return fail("through the drivers: write to the IMU pty " + pty_.slave_path() + ": " +
                  std::strerror(errno));
    written_.add();
  }
  done_.store(true, std::memory_order_release);
}

}  // namespace vigs::pipeline
