#include "drivers/v4l2/v4l2_rgbd_driver.hpp"

#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "core/config/camera_settings.hpp"
#include "core/config/rt_settings.hpp"
#include "rt/clock.hpp"
#include "rt/queue_policy.hpp"
#include "rt/thread_table.hpp"

namespace vigs::drivers {
namespace {

V4l2CaptureSettings node_settings(const V4l2RgbdDriverSettings& s, int which) {
  V4l2CaptureSettings n;
  n.device = which == 0 ? s.depth_device : s.colour_device;
  n.format = which == 0 ? V4l2PixelFormat::kZ16 : s.colour_format;
  n.width_px = s.width_px;
  n.height_px = s.height_px;
  n.rate_hz = s.rate_hz;
  n.buffers = s.buffers;
  return n;
}

std::int64_t half_period_us(double rate_hz) {
  return static_cast<std::int64_t>(std::llround(5e5 / std::max(rate_hz, 1.0)));
}

}  // namespace

V4l2RgbdDriverSettings v4l2_rgbd_settings(const config::CameraSettings& camera,
                                          const config::RtSettings& rt) {
  V4l2RgbdDriverSettings s;
  s.depth_device = camera.device;
  s.colour_device = camera.colour_device;
  const auto format = parse_pixel_format(camera.colour_format);
  if (!format || is_depth(*format)) {
    throw std::invalid_argument("camera.colour_format '" + camera.colour_format +
                                "' is not a V4L2 colour format (YUYV, MJPG, GREY)");
  }
  s.colour_format = *format;
  s.width_px = static_cast<std::uint32_t>(camera.width_px);
  s.height_px = static_cast<std::uint32_t>(camera.height_px);
  s.rate_hz = camera.rate_hz;
  s.realtime_thread = rt.realtime_priorities;
  s.pin_cpu = rt.pin_cpus;
  return s;
}

V4l2RgbdDriver::V4l2RgbdDriver(const V4l2RgbdDriverSettings& settings, rt::FramePool& pool,
                               rt::SpscRing<rt::FrameHandle>& out, V4l2DeviceOps& ops)
    : settings_(settings),
      pool_(pool),
      out_(out),
      ops_(ops),
      nodes_{V4l2Capture(ops, node_settings(settings, kDepth)),
             V4l2Capture(ops, node_settings(settings, kColour))},
      pairer_(settings.pair_tolerance_us > 0 ? settings.pair_tolerance_us
                                             : half_period_us(settings.rate_hz)),
      machine_(DeviceStateSettings{
          .frame_timeout_ns = rt::ms_to_ns(settings.frame_timeout_ms),
          .max_consecutive_errors =
              static_cast<std::uint32_t>(std::max(settings.max_consecutive_errors, 1)),
          .backoff_initial_ns = rt::ms_to_ns(settings.reopen_backoff_initial_ms),
          .backoff_max_ns = rt::ms_to_ns(
              std::max(settings.reopen_backoff_max_ms, settings.reopen_backoff_initial_ms)),
          .reopen = settings.reopen,
          .max_open_attempts = 0}) {
  const rt::FramePoolSettings& p = pool.settings();
  const bool grey_copy = settings.colour_format == V4l2PixelFormat::kGrey && p.colour_channels == 1;
  if (p.width != settings.width_px || p.height != settings.height_px ||
      (p.colour_channels != 3 && !grey_copy)) {
    throw std::invalid_argument(
        "V4l2RgbdDriver: frame pool holds " + std::to_string(p.width) + "x" +
        std::to_string(p.height) + " frames with " + std::to_string(p.colour_channels) +
        " colour channels; the camera needs " + std::to_string(settings.width_px) + "x" +
        std::to_string(settings.height_px) + " with 3 (1 for GREY)");
  }
  if (settings.wait_timeout_ms <= 0 || settings.frame_timeout_ms <= settings.wait_timeout_ms) {
    throw std::invalid_argument(
        "V4l2RgbdDriver: wait_timeout_ms must be > 0 and frame_timeout_ms > wait_timeout_ms");
  }
  if (settings.depth_device.empty() || settings.colour_device.empty()) {
    throw std::invalid_argument("V4l2RgbdDriver: both a depth and a colour node are needed");
  }
}

V4l2RgbdDriver::~V4l2RgbdDriver() {
  stop();
}

void V4l2RgbdDriver::open_nodes() {
  try {
    nodes_[kDepth].open();
    nodes_[kColour].open();
  } catch (...) {
    close_nodes();
    throw;
  }
  pairer_.reset();
  pending_[kDepth].reset();
  pending_[kColour].reset();
}

void V4l2RgbdDriver::close_nodes() noexcept {
  for (V4l2Capture& n : nodes_) {
    const V4l2CaptureCounters c = n.counters();
    kernel_dropped_.add(c.kernel_dropped);
    corrupt_.add(c.corrupt);
    host_stamped_.add(c.host_stamped);
    n.reset_counters();
    n.close();
  }
}

void V4l2RgbdDriver::start() {
  if (thread_) return;
  for (rt::SingleWriterCounter* c :
       {&depth_read_, &colour_read_, &frames_read_, &delivered_, &dropped_ring_full_,
        &dropped_pool_empty_, &unpaired_, &size_mismatch_, &read_errors_, &timeouts_, &reopens_,
        &convert_errors_, &kernel_dropped_, &corrupt_, &eagain_, &host_stamped_}) {
    c->reset();
  }
  tap_.reset();
  for (V4l2Capture& n : nodes_) n.reset_counters();
  machine_.reset(rt::monotonic_ns());
  if (!settings_.wait_for_device) {
    open_nodes();  // throws V4l2Error naming the node
    machine_.on_open_ok(rt::monotonic_ns());
  }
  last_t_ns_ = 0;
  end_of_stream_.store(false, std::memory_order_relaxed);
  state_.store(machine_.state(), std::memory_order_release);
  rt::ThreadSpec spec = rt::thread_spec("rgbd_driver");
  if (!settings_.realtime_thread) spec.sched_fifo_priority = 0;
  if (!settings_.pin_cpu) spec.cpu = -1;
  thread_.emplace(spec, [this](std::stop_token stop) { run(stop); });
}

void V4l2RgbdDriver::stop() {
  if (thread_) {
    thread_->request_stop();
    thread_->join();
    thread_.reset();
  }
  for (int s = 0; s < 2; ++s) requeue_pending(s);
  close_nodes();
}

void V4l2RgbdDriver::run(const std::stop_token& stop) noexcept {
  while (!stop.stop_requested()) {
    const std::int64_t now_ns = rt::monotonic_ns();
    switch (machine_.state()) {
      case DeviceState::kOpening:
        if (!machine_.due_to_open(now_ns)) {
          rt::sleep_until_ns(
              std::min(machine_.deadline_ns(), now_ns + rt::ms_to_ns(settings_.wait_timeout_ms)));
          break;
        }
        try {
          const bool first = machine_.counters().opens == 0;
          open_nodes();
          machine_.on_open_ok(rt::monotonic_ns());
          if (!first) reopens_.add();
        } catch (...) {
          machine_.on_open_failed(rt::monotonic_ns());
        }
        break;
      case DeviceState::kStreaming:
        stream_step();
        break;
      case DeviceState::kLost:
        for (int s = 0; s < 2; ++s) {
          if (pending_[s]) unpaired_.add();
          pending_[s].reset();  // its buffer dies with the mapping
        }
        close_nodes();
        machine_.on_closed(rt::monotonic_ns());
        break;
      case DeviceState::kEnded:
      case DeviceState::kFailed:
        finish_stream(stop);
        return;
    }
    state_.store(machine_.state(), std::memory_order_release);
  }
}

void V4l2RgbdDriver::stream_step() noexcept {
  pollfd fds[2] = {{nodes_[kDepth].fd(), POLLIN, 0}, {nodes_[kColour].fd(), POLLIN, 0}};
  const int n = ops_.poll(fds, 2, settings_.wait_timeout_ms);
  const std::int64_t now_ns = rt::monotonic_ns();
  if (n < 0) {
    if (errno != EINTR) {
      read_errors_.add();
      machine_.on_read_error(now_ns);
    }
    return;
  }
  if (n == 0) {
    timeouts_.add();
    (void)machine_.check_timeout(now_ns);
    return;
  }
  for (int s = 0; s < 2 && machine_.state() == DeviceState::kStreaming; ++s) {
    // POLLERR without POLLIN: the node is gone or stopped; DQBUF tells which (ENODEV / EINVAL).
    if ((fds[s].revents & (POLLIN | POLLERR | POLLHUP | POLLNVAL)) != 0) drain(s);
  }
  if (machine_.state() == DeviceState::kStreaming) (void)machine_.check_timeout(now_ns);
}

// Dequeues every buffer the node has ready (a burst after a preemption is caught up at once).
void V4l2RgbdDriver::drain(int s) noexcept {
  V4l2Capture& node = nodes_[s];
  for (int k = 0; k < 64 && machine_.state() == DeviceState::kStreaming; ++k) {
    V4l2Buffer b;
    switch (node.dequeue(b)) {
      case V4l2Capture::Dequeue::kFrame:
        machine_.on_frame(rt::monotonic_ns());
        on_buffer(s, b);
        break;
      case V4l2Capture::Dequeue::kCorrupt:
        break;  // counted and requeued by the node
      case V4l2Capture::Dequeue::kAgain:
        if (k == 0) eagain_.add();  // poll said ready, nothing to dequeue: a spurious wake-up
        return;
      case V4l2Capture::Dequeue::kGone:
        machine_.on_device_gone(rt::monotonic_ns());
        return;
      case V4l2Capture::Dequeue::kError:
        read_errors_.add();
        machine_.on_read_error(rt::monotonic_ns());
        return;
    }
  }
}

void V4l2RgbdDriver::requeue_pending(int s) noexcept {
  if (pending_[s] && nodes_[s].is_open()) (void)nodes_[s].requeue(pending_[s]->index);
  pending_[s].reset();
}

void V4l2RgbdDriver::on_buffer(int s, const V4l2Buffer& b) noexcept {
  (s == kDepth ? depth_read_ : colour_read_).add();
  const std::size_t w = settings_.width_px, h = settings_.height_px;
  const std::size_t bpp = s == kDepth ? 2 : raw_bytes_per_pixel(settings_.colour_format);
  const std::size_t need = bpp == 0 ? 1 : nodes_[s].bytes_per_line() * (h - 1) + w * bpp;
  if (b.bytes_used < need) {
    size_mismatch_.add();  // a short buffer: counted and skipped, never paired
    (void)nodes_[s].requeue(b.index);
    return;
  }
  const std::int64_t t_us = b.t_ns / rt::kNsPerUs;
  const bool displaced = s == kDepth ? pairer_.add_depth(t_us) : pairer_.add_colour(t_us);
  if (displaced) {
    unpaired_.add();
    requeue_pending(s);
  }
  pending_[s] = b;
  switch (pairer_.step()) {
    case PairStep::kWait:
      break;
    case PairStep::kPair:
      emit_pair();
      break;
    case PairStep::kDiscardDepth:
      unpaired_.add();
      requeue_pending(kDepth);
      break;
    case PairStep::kDiscardColour:
      unpaired_.add();
      requeue_pending(kColour);
      break;
  }
}

void V4l2RgbdDriver::emit_pair() noexcept {
  const V4l2Buffer& d = *pending_[kDepth];
  const V4l2Buffer& c = *pending_[kColour];
  std::int64_t t_ns = d.t_ns;  // the depth buffer's kernel stamp, or its sync edge's
  if (trigger_ != nullptr) {
    if (const auto edge = trigger_->match(t_ns)) t_ns = *edge;
  }
  rt::FrameHandle handle = pool_.acquire();
  if (!handle.valid()) {
    frames_read_.add();
    dropped_pool_empty_.add();
  } else {
    rt::Frame& frame = pool_.frame(handle);
    const std::size_t w = settings_.width_px, h = settings_.height_px;
    const std::size_t depth_row = w * 2;
    const std::size_t stride = nodes_[kDepth].bytes_per_line();
    auto* dst = reinterpret_cast<std::uint8_t*>(frame.depth.data());
    if (stride == depth_row) {
      std::memcpy(dst, d.data, depth_row * h);
    } else {
      for (std::size_t y = 0; y < h; ++y)
        std::memcpy(dst + y * depth_row, d.data + y * stride, depth_row);
    }
    bool ok = true;
    if (pool_.settings().colour_channels == 1) {  // GREY into a mono pool: a copy
      const std::size_t cs = nodes_[kColour].bytes_per_line();
      for (std::size_t y = 0; y < h; ++y)
        std::memcpy(frame.colour.data() + y * w, c.data + y * cs, w);
    } else {
      ok = nodes_[kColour].converter()->to_rgb8({c.data, c.bytes_used}, frame.colour);
    }
    if (!ok) {
      convert_errors_.add();  // a corrupt MJPEG frame, for instance: not a frame of the stream
      pool_.release(handle);
    } else {
      frame.t_ns = std::max(t_ns, last_t_ns_ + 1);
      last_t_ns_ = frame.t_ns;
      frame.sequence = frames_read_.get();
      frames_read_.add();
      tap_.offer(pool_, handle);
      frame.arrival_ns = rt::monotonic_ns();
      if (rt::push_or_drop(out_, handle, dropped_ring_full_,
                           [this](rt::FrameHandle& hd) noexcept { pool_.release(hd); })) {
        delivered_.add();
      }
    }
  }
  requeue_pending(kDepth);
  requeue_pending(kColour);
}

void V4l2RgbdDriver::finish_stream(const std::stop_token& stop) noexcept {
  for (int s = 0; s < 2; ++s) {
    if (pending_[s]) unpaired_.add();
    requeue_pending(s);
  }
  end_of_stream_.store(true, std::memory_order_release);
  while (!stop.stop_requested()) {
    if (out_.try_push(rt::FrameHandle{})) return;
    rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(1));
  }
}

V4l2RgbdCounters V4l2RgbdDriver::counters() const noexcept {
  V4l2RgbdCounters v;
  RgbdDriverCounters& c = v.rgbd;
  c.end_of_stream = end_of_stream();
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
  const DeviceStateCounters m = machine_.counters();
  c.opens = m.opens;
  c.open_failures = m.open_failures;
  c.losses = m.losses;
  c.frame_timeouts = m.frame_timeouts;
  c.error_resets = m.error_resets;
  c.device_gone = m.device_gone;
  c.reopens = reopens_.get();
  c.tap_dropped = tap_.dropped();
  v.convert_errors = convert_errors_.get();
  v.kernel_dropped = kernel_dropped_.get();
  v.corrupt_buffers = corrupt_.get();
  v.eagain = eagain_.get();
  v.host_stamped = host_stamped_.get();
  for (const V4l2Capture& n : nodes_) {
    const V4l2CaptureCounters k = n.counters();
    v.kernel_dropped += k.kernel_dropped;
    v.corrupt_buffers += k.corrupt;
    v.host_stamped += k.host_stamped;
  }
  return v;
}

const rt::ThreadApplyStatus* V4l2RgbdDriver::thread_status() const noexcept {
  return thread_ ? &thread_->status() : nullptr;
}

}  // namespace vigs::drivers
