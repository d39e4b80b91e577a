#include "pipeline/live_camera.hpp"

#include <stdexcept>
#include <string>

namespace vigs::pipeline {
namespace {

// Edges waiting for their frames: a few frame periods (the matcher's window takes them at once).
constexpr std::size_t kEdgeRing = 64;

}  // namespace

std::unique_ptr<LiveCamera> LiveCamera::robot(const config::RobotConfig& cfg, rt::FramePool& pool,
                                              rt::SpscRing<rt::FrameHandle>& frames,
                                              const LiveCameraSeams& seams) {
  const config::CameraSettings& c = cfg.camera;
  if (c.driver != "openni2" && c.driver != "v4l2")
    throw std::runtime_error("live sensors need camera.driver openni2 or v4l2, not '" + c.driver +
                             "'");
  std::unique_ptr<LiveCamera> cam(new LiveCamera());
  if (!c.trigger_chip.empty()) {  // frame sync, as `vigs record` decides it
    cam->edges_ = std::make_unique<rt::SpscRing<drivers::TriggerEdge>>(kEdgeRing);
    cam->trigger_ = std::make_unique<drivers::GpioTrigger>(
        drivers::gpio_trigger_settings(c, cfg.rt), *cam->edges_);
    cam->matcher_ = std::make_unique<drivers::TriggerMatcher>(
        *cam->edges_, drivers::trigger_match_settings(c.trigger_tolerance_ms, c.trigger_offset_ms));
    cam->trigger_event_fd_ = seams.trigger_event_fd;
  }
  if (c.driver == "openni2") {
    cam->openni2_ = std::make_unique<drivers::Openni2Driver>(drivers::openni2_settings(c, cfg.rt),
                                                             pool, frames);
    cam->openni2_->set_trigger(cam->matcher_.get());
  } else {
    drivers::V4l2DeviceOps& ops =
        seams.v4l2_ops != nullptr ? *seams.v4l2_ops : drivers::libv4l2_device_ops();
    cam->v4l2_ = std::make_unique<drivers::V4l2RgbdDriver>(drivers::v4l2_rgbd_settings(c, cfg.rt),
                                                           pool, frames, ops);
    cam->v4l2_->set_trigger(cam->matcher_.get());
  }
  return cam;
}

std::unique_ptr<LiveCamera> LiveCamera::openni2(const drivers::Openni2DriverSettings& settings,
                                                rt::FramePool& pool,
                                                rt::SpscRing<rt::FrameHandle>& frames) {
  std::unique_ptr<LiveCamera> cam(new LiveCamera());
  cam->openni2_ = std::make_unique<drivers::Openni2Driver>(settings, pool, frames);
  return cam;
}

LiveCamera::~LiveCamera() {
  stop();
}

void LiveCamera::set_tap(rt::SpscRing<rt::FrameHandle>* tap) noexcept {
  if (openni2_) openni2_->set_tap(tap);
  if (v4l2_) v4l2_->set_tap(tap);
}

void LiveCamera::set_edge_tap(rt::SpscRing<drivers::TriggerEdge>* tap) noexcept {
  if (trigger_) trigger_->set_tap(tap);
}

void LiveCamera::start() {
  try {
    if (trigger_) {
      if (trigger_event_fd_ >= 0) {
        trigger_->start_with_event_fd(trigger_event_fd_);
      } else {
        trigger_->start();  // throws GpioTriggerError naming the chip and line
      }
    }
    if (openni2_) openni2_->start();
    if (v4l2_) v4l2_->start();
  } catch (...) {
    stop();
    throw;
  }
}

void LiveCamera::stop() {
  if (openni2_) openni2_->stop();
  if (v4l2_) v4l2_->stop();
  if (trigger_) trigger_->stop();
}

drivers::RgbdDriverCounters LiveCamera::counters() const noexcept {
  if (openni2_) return openni2_->counters();
  if (v4l2_) return v4l2_->counters().rgbd;
  return {};
}

std::uint64_t LiveCamera::losses() const noexcept {
  return counters().losses;
}

std::optional<drivers::GpioTriggerCounters> LiveCamera::trigger_counters() const noexcept {
  if (!trigger_) return std::nullopt;
  return trigger_->counters();
}

std::optional<drivers::TriggerMatchCounters> LiveCamera::trigger_match_counters() const noexcept {
  if (!matcher_) return std::nullopt;
  return matcher_->counters();
}

}  // namespace vigs::pipeline
