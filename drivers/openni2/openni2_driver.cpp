#include "drivers/openni2/openni2_driver.hpp"

#include <OpenNI.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string_view>

#include "core/config/camera_settings.hpp"
#include "core/config/rt_settings.hpp"
#include "rt/clock.hpp"
#include "rt/poll.hpp"
#include "rt/queue_policy.hpp"
#include "rt/thread_table.hpp"

namespace vigs::drivers {
namespace {

constexpr int kDepth = 0;
constexpr int kColour = 1;
constexpr std::size_t kDepthBytesPerPixel = 2;   // PIXEL_FORMAT_DEPTH_1_MM
constexpr std::size_t kColourBytesPerPixel = 3;  // PIXEL_FORMAT_RGB888

bool looks_like_file(std::string_view uri) {
  if (uri.size() < 4) return false;
  std::string ext(uri.substr(uri.size() - 4));
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".oni";
}

std::string size_text(int w, int h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

std::string mode_text(const openni::VideoMode& m) {
  return size_text(m.getResolutionX(), m.getResolutionY()) + " format " +
         std::to_string(static_cast<int>(m.getPixelFormat())) + " at " +
         std::to_string(m.getFps()) + " fps";
}

// Copies `rows` rows of `row_bytes` from a frame whose rows are `stride` bytes apart.
void copy_rows(const openni::VideoFrameRef& f, std::uint8_t* dst, std::size_t row_bytes,
               std::size_t rows) noexcept {
  const auto* src = static_cast<const std::uint8_t*>(f.getData());
  const auto stride = static_cast<std::size_t>(f.getStrideInBytes());
  if (stride == row_bytes) {
    std::memcpy(dst, src, row_bytes * rows);
    return;
  }
  for (std::size_t y = 0; y < rows; ++y)
    std::memcpy(dst + y * row_bytes, src + y * stride, row_bytes);
}

}  // namespace

struct Openni2Driver::Device {
  bool initialized = false;  // OpenNI::initialize succeeded (reference counted by OpenNI2)
  openni::Device device;
  openni::VideoStream streams[2];            // kDepth, kColour
  openni::VideoFrameRef pending[2];          // frames waiting for a partner
  openni::VideoFrameRef incoming;            // the frame just read
  std::int64_t pending_read_ns[2] = {0, 0};  // host time each pending frame was read
  int last_index[2] = {0, 0};                // playback: last frame number seen per stream
  bool clip_restarted = false;               // playback: a frame number went back (repeat wrapped)
  std::uint64_t frames_this_open[2] = {0, 0};  // frames read since this device was opened
};

Openni2DriverSettings openni2_settings(const config::CameraSettings& camera,
                                       const config::RtSettings& rt) {
  Openni2DriverSettings s;
  s.uri = camera.device;
  s.width_px = static_cast<std::uint32_t>(camera.width_px);
  s.height_px = static_cast<std::uint32_t>(camera.height_px);
  s.rate_hz = camera.rate_hz;
  s.realtime_thread = rt.realtime_priorities;
  s.pin_cpu = rt.pin_cpus;
  return s;
}

Openni2Driver::Openni2Driver(const Openni2DriverSettings& settings, rt::FramePool& pool,
                             rt::SpscRing<rt::FrameHandle>& out)
    : settings_(settings),
      pool_(pool),
      out_(out),
      // Half a frame period: frames of one instant pair, neighbours never do.
      pairer_(static_cast<std::int64_t>(std::llround(5e5 / std::max(settings.rate_hz, 1.0)))),
      pacer_(settings.playback_speed, rt::ms_to_ns(std::max(settings.max_hold_ms, 1))),
      machine_(DeviceStateSettings{
          .frame_timeout_ns = rt::ms_to_ns(settings.frame_timeout_ms),
          .max_consecutive_errors =
              static_cast<std::uint32_t>(std::max(settings.max_consecutive_errors, 1)),
          .backoff_initial_ns = rt::ms_to_ns(settings.reopen_backoff_initial_ms),
          .backoff_max_ns = rt::ms_to_ns(
              std::max(settings.reopen_backoff_max_ms, settings.reopen_backoff_initial_ms)),
          .reopen = looks_like_file(settings.uri) ? settings.reopen_files : settings.reopen_live,
          .max_open_attempts = 0}) {
  const rt::FramePoolSettings& p = pool.settings();
  if (p.width != settings.width_px || p.height != settings.height_px || p.colour_channels != 3) {
    throw std::invalid_argument(
        "Openni2Driver: frame pool holds " +
        size_text(static_cast<int>(p.width), static_cast<int>(p.height)) + " frames with " +
        std::to_string(p.colour_channels) + " colour channels; the camera needs " +
        size_text(static_cast<int>(settings.width_px), static_cast<int>(settings.height_px)) +
        " rgb8 (3 channels)");
  }
  if (settings.wait_timeout_ms <= 0 || settings.frame_timeout_ms <= settings.wait_timeout_ms ||
      settings.reopen_backoff_initial_ms <= 0) {
    throw std::invalid_argument(
        "Openni2Driver: wait_timeout_ms must be > 0, frame_timeout_ms > wait_timeout_ms, "
        "reopen_backoff_initial_ms > 0");
  }
  const std::string& uri = settings.uri;
  what_ = (looks_like_file(uri) ? "ONI file '" : "OpenNI2 device '") +
          (uri.empty() ? std::string("(any)") : uri) + "'";
}

Openni2Driver::~Openni2Driver() {
  stop();
}

void Openni2Driver::open_device() {
  const std::string& uri = settings_.uri;
  const std::string& what = what_;
  if (looks_like_file(uri)) {
    struct stat st {};
    if (::stat(uri.c_str(), &st) != 0) throw Openni2Error(what + ": " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw Openni2Error(what + ": not a regular file");
  }
  device_ = std::make_unique<Device>();
  Device& d = *device_;
  try {
    if (openni::OpenNI::initialize() != openni::STATUS_OK) {
      throw Openni2Error(what +
                         ": OpenNI2 initialisation failed: " + openni::OpenNI::getExtendedError());
    }
    d.initialized = true;
    if (d.device.open(uri.empty() ? openni::ANY_DEVICE : uri.c_str()) != openni::STATUS_OK) {
      throw Openni2Error(what + ": OpenNI2 cannot open it" +
                         (looks_like_file(uri) ? " (not a readable ONI recording?)" : "") + ": " +
                         openni::OpenNI::getExtendedError());
    }
    const bool is_file = d.device.isFile();
    is_file_.store(is_file, std::memory_order_relaxed);
    paced_ = is_file && settings_.playback_speed > 0.0;
    if (is_file) {
      // Manual mode in both cases: real time is paced by the driver (hold_until_due).
      openni::PlaybackControl* playback = d.device.getPlaybackControl();
      const float speed = -1.0f;
      if (playback == nullptr || playback->setSpeed(speed) != openni::STATUS_OK) {
        throw Openni2Error(what + ": cannot set the playback speed (setSpeed(" +
                           std::to_string(speed) + "))");
      }
      // Repeat stays on: with it off, OpenNI2 2.2's player thread spins after the End record
      // and closing the streams crashes libOniFile now and then (tests/io/test_oni_playback.cpp).
      // The driver detects the end itself and stops reading, which parks the player.
      (void)playback->setRepeatEnabled(true);
    }
    const openni::SensorType sensors[2] = {openni::SENSOR_DEPTH, openni::SENSOR_COLOR};
    const openni::PixelFormat formats[2] = {openni::PIXEL_FORMAT_DEPTH_1_MM,
                                            openni::PIXEL_FORMAT_RGB888};
    const char* names[2] = {"depth", "colour"};
    const int w = static_cast<int>(settings_.width_px);
    const int h = static_cast<int>(settings_.height_px);
    for (int s = 0; s < 2; ++s) {
      if (!d.device.hasSensor(sensors[s]) ||
          d.streams[s].create(d.device, sensors[s]) != openni::STATUS_OK) {
        throw Openni2Error(what + ": no " + names[s] +
                           " stream: " + openni::OpenNI::getExtendedError());
      }
      if (!is_file) {
        // Live sensor: pick the configured size, format and rate among the supported modes.
        const openni::SensorInfo& info = d.streams[s].getSensorInfo();
        const openni::Array<openni::VideoMode>& modes = info.getSupportedVideoModes();
        const int fps = static_cast<int>(std::lround(settings_.rate_hz));
        bool set = false;
        std::string offered;
        for (int m = 0; m < modes.getSize() && !set; ++m) {
          const openni::VideoMode& mode = modes[m];
          offered += (m ? ", " : "") + mode_text(mode);
          if (mode.getResolutionX() == w && mode.getResolutionY() == h &&
              mode.getPixelFormat() == formats[s] && mode.getFps() == fps) {
            set = d.streams[s].setVideoMode(mode) == openni::STATUS_OK;
          }
        }
        if (!set) {
          throw Openni2Error(what + ": " + names[s] + " stream has no mode " + size_text(w, h) +
                             " format " + std::to_string(static_cast<int>(formats[s])) + " at " +
                             std::to_string(fps) + " fps (offered: " + offered + ")");
        }
      }
      const openni::VideoMode mode = d.streams[s].getVideoMode();
      if (mode.getResolutionX() != w || mode.getResolutionY() != h) {
        throw Openni2Error(what + ": " + names[s] + " frames are " +
                           size_text(mode.getResolutionX(), mode.getResolutionY()) +
                           " but the camera is configured as " + size_text(w, h));
      }
      if (mode.getPixelFormat() != formats[s]) {
        throw Openni2Error(what + ": " + names[s] + " pixel format is " +
                           std::to_string(static_cast<int>(mode.getPixelFormat())) + ", need " +
                           std::to_string(static_cast<int>(formats[s])) +
                           (s == kDepth ? " (DEPTH_1_MM)" : " (RGB888)"));
      }
    }
    if (is_file) {
      openni::PlaybackControl* playback = d.device.getPlaybackControl();
      const int nd = playback->getNumberOfFrames(d.streams[kDepth]);
      const int nc = playback->getNumberOfFrames(d.streams[kColour]);
      if (nd <= 0 || nc <= 0) throw Openni2Error(what + ": the clip holds no frames");
      clip_depth_frames_ = static_cast<std::uint64_t>(nd);
      clip_colour_frames_ = static_cast<std::uint64_t>(nc);
    }
    bool registered = false;
    if (settings_.register_depth &&
        d.device.isImageRegistrationModeSupported(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR)) {
      registered = d.device.setImageRegistrationMode(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR) ==
                   openni::STATUS_OK;
    }
    registered_.store(registered, std::memory_order_relaxed);
    if (!is_file) (void)d.device.setDepthColorSyncEnabled(true);  // best effort
    for (int s = 0; s < 2; ++s) {
      if (d.streams[s].start() != openni::STATUS_OK) {
        throw Openni2Error(what + ": cannot start the " + names[s] +
                           " stream: " + openni::OpenNI::getExtendedError());
      }
    }
  } catch (...) {
    close_device();
    throw;
  }
  // Fresh per-connection state: a reopened device gets a new clock anchor and pairer.
  pairer_.reset();
  clock_.reset();
  pacer_.reset();
}

void Openni2Driver::start() {
  if (thread_) return;
  // Fresh state for this run (the thread does not exist yet, so these writes do not race).
  machine_.reset(rt::monotonic_ns());
  fault_text_[0] = '\0';
  if (!settings_.wait_for_device) {
    open_device();  // throws naming the URI; nothing is left open
    machine_.reset(rt::monotonic_ns());
    machine_.on_open_ok(rt::monotonic_ns());
  }
  state_.store(machine_.state(), std::memory_order_release);
  for (rt::SingleWriterCounter* c :
       {&depth_read_, &colour_read_, &frames_read_, &delivered_, &dropped_ring_full_,
        &dropped_pool_empty_, &unpaired_, &size_mismatch_, &read_errors_, &timeouts_,
        &clock_reanchors_, &playback_skipped_, &reopens_}) {
    c->reset();
  }
  tap_.reset();
  end_of_stream_.store(false, std::memory_order_relaxed);
  host_minus_device_ns_.store(kNoAnchor, std::memory_order_relaxed);

  rt::ThreadSpec spec = rt::thread_spec("rgbd_driver");
  if (!settings_.realtime_thread) spec.sched_fifo_priority = 0;
  if (!settings_.pin_cpu) spec.cpu = -1;
  thread_.emplace(spec, [this](std::stop_token stop) { run(stop); });
}

void Openni2Driver::stop() {
  if (thread_) {
    thread_->request_stop();
    thread_->join();
    thread_.reset();
  }
  close_device();
}

void Openni2Driver::close_device() noexcept {
  if (!device_) return;
  Device& d = *device_;
  for (auto& f : d.pending) f.release();
  d.incoming.release();
  // Both streams stop before either is destroyed. OpenNI2 2.2's file player walks its stream list
  // without a lock on every turn of its loop (PlayerDevice::MainLoop; a tight loop while a stream
  // is started and the clip is cut short) and destroying a stream removes it unlocked: destroying
  // one while the other was still started crashed libOniFile (3 in 90 runs of the truncated-clip
  // test, core dump). Once none is started the player only looks every 10 ms, so wait past that.
  bool any = false;
  for (auto& s : d.streams) {
    if (s.isValid()) {
      s.stop();
      any = true;
    }
  }
  if (any && is_file()) rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(25));
  for (auto& s : d.streams) {
    if (s.isValid()) s.destroy();
  }
  if (d.device.isValid()) d.device.close();
  if (d.initialized) openni::OpenNI::shutdown();
  device_.reset();
}

void Openni2Driver::run(const std::stop_token& stop) noexcept {
  stop_ = &stop;
  while (!stop.stop_requested()) {
    switch (machine_.state()) {
      case DeviceState::kOpening:
        try_reopen();
        break;
      case DeviceState::kStreaming:
        stream_step();
        break;
      case DeviceState::kLost:
        lose_device();
        break;
      case DeviceState::kEnded:
      case DeviceState::kFailed:
        finish_stream(stop);
        return;
    }
    state_.store(machine_.state(), std::memory_order_release);
  }
}

void Openni2Driver::stream_step() noexcept {
  Device& d = *device_;
  openni::VideoStream* streams[2] = {&d.streams[kDepth], &d.streams[kColour]};
  int ready = -1;
  // Lockstep playback: this wait is also what makes OpenNI2's player deliver the next record.
  const openni::Status rc =
      openni::OpenNI::waitForAnyStream(streams, 2, &ready, settings_.wait_timeout_ms);
  const std::int64_t now_ns = rt::monotonic_ns();
  if (rc == openni::STATUS_TIME_OUT) {
    timeouts_.add();
    (void)machine_.check_timeout(now_ns);  // the progress watchdog
    return;
  }
  if (rc != openni::STATUS_OK || (ready != kDepth && ready != kColour)) {
    read_errors_.add();
    machine_.on_read_error(now_ns);
    if (machine_.state() == DeviceState::kStreaming) {
      rt::sleep_until_ns(now_ns + rt::ms_to_ns(settings_.wait_timeout_ms));
      (void)machine_.check_timeout(rt::monotonic_ns());
    }
    return;
  }
  if (read_one(ready)) {
    machine_.on_frame(now_ns);
  } else if (!d.clip_restarted) {
    machine_.on_read_error(now_ns);
  }
  if (is_file() && (d.clip_restarted || (d.frames_this_open[kDepth] >= clip_depth_frames_ &&
                                         d.frames_this_open[kColour] >= clip_colour_frames_))) {
    // A player that skipped (not in manual mode, which the driver uses) may have wrapped past
    // the last frames before they were read.
    const auto last = static_cast<std::uint64_t>(std::max(d.last_index[kDepth], 0));
    if (last < clip_depth_frames_) playback_skipped_.add(clip_depth_frames_ - last);
    machine_.on_end_of_stream();
  } else {
    (void)machine_.check_timeout(now_ns);
  }
}

// kOpening: waits for the next attempt (in wait_timeout_ms steps, so stop() stays prompt), then
// opens the device by URI. Recovery path: OpenNI2 allocates here, the driver's strings too.
void Openni2Driver::try_reopen() noexcept {
  const std::int64_t now_ns = rt::monotonic_ns();
  if (!machine_.due_to_open(now_ns)) {
    rt::sleep_until_ns(
        std::min(machine_.deadline_ns(), now_ns + rt::ms_to_ns(settings_.wait_timeout_ms)));
    return;
  }
  const bool first = machine_.counters().opens == 0;
  try {
    open_device();
    machine_.on_open_ok(rt::monotonic_ns());
    if (!first) reopens_.add();
  } catch (const std::exception& e) {
    set_fault_text(e.what());
    machine_.on_open_failed(rt::monotonic_ns());
  } catch (...) {
    set_fault_text("unknown error while opening");
    machine_.on_open_failed(rt::monotonic_ns());
  }
}

// kLost: what is pending can find no partner any more; close, so the next open starts clean.
void Openni2Driver::lose_device() noexcept {
  if (device_) {
    for (auto& f : device_->pending) {
      if (f.isValid()) unpaired_.add();
    }
  }
  char text[kFaultTextBytes];
  const DeviceFault why = machine_.last_fault();
  if (why == DeviceFault::kFrameTimeout && is_file()) {
    std::snprintf(text, sizeof text,
                  "%s: playback made no progress for %d ms after %llu of %llu depth frames "
                  "(a truncated or damaged clip?)",
                  what_.c_str(), settings_.frame_timeout_ms,
                  static_cast<unsigned long long>(device_ ? device_->frames_this_open[kDepth] : 0),
                  static_cast<unsigned long long>(clip_depth_frames_));
  } else {
    const std::string_view why_text = to_string(why);
    std::snprintf(text, sizeof text, "%s: stream lost (%.*s) after %llu frames", what_.c_str(),
                  static_cast<int>(why_text.size()), why_text.data(),
                  static_cast<unsigned long long>(frames_read_.get()));
  }
  set_fault_text(text);
  close_device();
  machine_.on_closed(rt::monotonic_ns());
}

void Openni2Driver::set_fault_text(const char* text) noexcept {
  std::snprintf(fault_text_.data(), fault_text_.size(), "%s", text);
}

bool Openni2Driver::read_one(int s) noexcept {
  Device& d = *device_;
  if (d.streams[s].readFrame(&d.incoming) != openni::STATUS_OK || !d.incoming.isValid()) {
    read_errors_.add();
    return false;
  }
  const std::int64_t t_read_ns = rt::monotonic_ns();
  if (is_file_) {
    // With repeat on, a frame number that does not increase means the clip started over: that
    // frame is not part of this run; run() ends the stream.
    if (d.incoming.getFrameIndex() <= d.last_index[s]) {
      d.incoming.release();
      d.clip_restarted = true;
      return false;
    }
    // A frame number that jumps: frames the player replaced unread (numbers start at 1). Manual
    // mode never does; counted so that a player that does is seen.
    if (s == kDepth && d.incoming.getFrameIndex() > d.last_index[s] + 1)
      playback_skipped_.add(
          static_cast<std::uint64_t>(d.incoming.getFrameIndex() - d.last_index[s] - 1));
    d.last_index[s] = d.incoming.getFrameIndex();
  }
  (s == kDepth ? depth_read_ : colour_read_).add();
  ++d.frames_this_open[s];

  const std::size_t bpp = s == kDepth ? kDepthBytesPerPixel : kColourBytesPerPixel;
  const openni::PixelFormat want =
      s == kDepth ? openni::PIXEL_FORMAT_DEPTH_1_MM : openni::PIXEL_FORMAT_RGB888;
  const auto w = static_cast<int>(settings_.width_px);
  const auto h = static_cast<int>(settings_.height_px);
  const std::size_t row_bytes = settings_.width_px * bpp;
  const openni::VideoFrameRef& f = d.incoming;
  if (f.getWidth() != w || f.getHeight() != h || f.getVideoMode().getPixelFormat() != want ||
      static_cast<std::size_t>(f.getStrideInBytes()) < row_bytes ||
      static_cast<std::size_t>(f.getDataSize()) <
          static_cast<std::size_t>(f.getStrideInBytes()) * (settings_.height_px - 1) + row_bytes) {
    size_mismatch_.add();  // counted and skipped, never paired
    d.incoming.release();
    return true;  // the device delivers: not a fault of the stream
  }

  const auto t_device_us = static_cast<std::int64_t>(f.getTimestamp());
  const bool displaced =
      s == kDepth ? pairer_.add_depth(t_device_us) : pairer_.add_colour(t_device_us);
  if (displaced) unpaired_.add();
  d.pending[s] = d.incoming;  // reference counted by OpenNI2; replaces (releases) the old one
  d.pending_read_ns[s] = t_read_ns;
  d.incoming.release();

  switch (pairer_.step()) {
    case PairStep::kWait:
      break;
    case PairStep::kPair:
      emit_pair();
      break;
    case PairStep::kDiscardDepth:
      unpaired_.add();
      d.pending[kDepth].release();
      break;
    case PairStep::kDiscardColour:
      unpaired_.add();
      d.pending[kColour].release();
      break;
  }
  return true;
}

void Openni2Driver::emit_pair() noexcept {
  Device& d = *device_;
  const std::uint64_t sequence = frames_read_.get();
  frames_read_.add();
  // Stamp every pair (also the dropped ones) so the clock map sees the device time advance.
  std::int64_t t_ns =
      clock_.to_host_ns(static_cast<std::int64_t>(d.pending[kDepth].getTimestamp()),
                        std::max(d.pending_read_ns[kDepth], d.pending_read_ns[kColour]));
  clock_reanchors_.add(clock_.reanchors() - clock_reanchors_.get());
  host_minus_device_ns_.store(clock_.offset_ns(), std::memory_order_release);
  if (paced_) hold_until_due(static_cast<std::int64_t>(d.pending[kDepth].getTimestamp()) * 1000);
  if (trigger_ != nullptr) {
    if (const auto edge = trigger_->match(t_ns)) t_ns = *edge;
    t_ns = std::max(t_ns, last_synced_t_ns_ + 1);  // mixed edge / device stamps stay ordered
    last_synced_t_ns_ = t_ns;
  }

  rt::FrameHandle handle = pool_.acquire();
  if (!handle.valid()) {
    dropped_pool_empty_.add();
  } else {
    rt::Frame& frame = pool_.frame(handle);
    copy_rows(d.pending[kDepth], reinterpret_cast<std::uint8_t*>(frame.depth.data()),
              settings_.width_px * kDepthBytesPerPixel, settings_.height_px);
    copy_rows(d.pending[kColour], frame.colour.data(), settings_.width_px * kColourBytesPerPixel,
              settings_.height_px);
    frame.t_ns = t_ns;
    frame.sequence = sequence;
    tap_.offer(pool_, handle);
    frame.arrival_ns = rt::monotonic_ns();
    if (rt::push_or_drop(out_, handle, dropped_ring_full_,
                         [this](rt::FrameHandle& h) noexcept { pool_.release(h); })) {
      delivered_.add();
    }
  }
  d.pending[kDepth].release();
  d.pending[kColour].release();
}

void Openni2Driver::hold_until_due(std::int64_t t_device_ns) noexcept {
  const std::int64_t due_ns = pacer_.due_ns(t_device_ns, rt::monotonic_ns());
  // In wait_timeout_ms steps, so stop() stays as prompt as in the read loop.
  (void)rt::sleep_until_or_stop(due_ns, *stop_, rt::ms_to_ns(settings_.wait_timeout_ms));
}

void Openni2Driver::finish_stream(const std::stop_token& stop) noexcept {
  if (device_) {
    for (auto& f : device_->pending) {
      if (f.isValid()) {
        unpaired_.add();
        f.release();
      }
    }
  }
  pairer_.reset();
  if (machine_.state() == DeviceState::kEnded) fault_text_[0] = '\0';
  end_of_stream_.store(true, std::memory_order_release);  // last: counters are final
  // End-of-stream marker: an invalid handle. Shutdown is not real-time, so wait for room.
  while (!stop.stop_requested()) {
    if (out_.try_push(rt::FrameHandle{})) return;
    rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(1));
  }
}

RgbdDriverCounters Openni2Driver::counters() const noexcept {
  RgbdDriverCounters c;
  c.end_of_stream = end_of_stream();  // first: when true, the counters below are final
  c.depth_read = depth_read_.get();
  c.colour_read = colour_read_.get();
  c.frames_read = frames_read_.get();
  c.delivered = delivered_.get();
  c.dropped_ring_full = dropped_ring_full_.get();
  c.dropped_pool_empty = dropped_pool_empty_.get();
  c.unpaired = unpaired_.get();
  c.size_mismatch = size_mismatch_.get();
  c.read_errors = read_errors_.get();
  c.timeouts = timeouts_.get();
  c.clock_reanchors = clock_reanchors_.get();
  c.playback_skipped = playback_skipped_.get();
  const DeviceStateCounters m = machine_.counters();
  c.opens = m.opens;
  c.open_failures = m.open_failures;
  c.losses = m.losses;
  c.frame_timeouts = m.frame_timeouts;
  c.error_resets = m.error_resets;
  c.device_gone = m.device_gone;
  c.reopens = reopens_.get();
  c.tap_dropped = tap_.dropped();
  return c;
}

DeviceFault Openni2Driver::fault() const noexcept {
  if (!end_of_stream() || state() != DeviceState::kFailed) return DeviceFault::kNone;
  return machine_.last_fault();
}

std::string Openni2Driver::fault_message() const {
  if (fault() == DeviceFault::kNone) return {};
  return std::string(fault_text_.data());
}

const rt::ThreadApplyStatus* Openni2Driver::thread_status() const noexcept {
  return thread_ ? &thread_->status() : nullptr;
}

}  // namespace vigs::drivers
