#pragma once
// LiveCamera: the live pipeline's camera driver thread(s), whichever camera.driver the robot has,
// into the pipeline's FramePool and frame ring:
//   openni2  Openni2Driver (a device, or the .oni clip of `--through-drivers`)
//   v4l2     V4l2RgbdDriver (a Z16 depth node + a colour node)
// and, for a live camera with camera.trigger_chip set (as `vigs record` decides it), the GPIO
// frame sync: GpioTrigger on the thread table's `gpio_trigger` thread pushes each strobe edge into
// a TriggerMatcher, which restamps every frame with its edge on the camera driver's thread.
// Threads take their table entries (rt/thread_table.hpp) with rt.realtime_priorities /
// rt.pin_cpus applied, as the spine's other drivers. start(): trigger first (no frame is formed
// before its edge can be), camera last; stop(): camera first, then the trigger; both joined.
// counters() and losses() are relaxed snapshots of the running driver's counters (noexcept, no
// allocation or lock: callable from the tracker thread).
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "core/config/robot_config.hpp"
#include "drivers/common/rgbd_driver_counters.hpp"
#include "drivers/common/trigger_edge.hpp"
#include "drivers/common/trigger_matcher.hpp"
#include "drivers/gpio_trigger/gpio_trigger.hpp"
#include "drivers/openni2/openni2_driver.hpp"
#include "drivers/v4l2/v4l2_device_ops.hpp"
#include "drivers/v4l2/v4l2_rgbd_driver.hpp"
#include "rt/frame_pool.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::pipeline {

/// Test seams at the kernel boundaries (no video device or gpiochip in tests). Defaults: the real
/// ones.
struct LiveCameraSeams {
  /// v4l2: the device operations (tests: a fake with the kernel's semantics); null: libv4l2.
  drivers::V4l2DeviceOps* v4l2_ops = nullptr;
  /// Frame sync: >= 0, the kernel's gpioevent_data records are read from this fd (not owned)
  /// instead of camera.trigger_chip / trigger_line (tests: a pipe); -1: the line.
  int trigger_event_fd = -1;
};

class LiveCamera {
 public:
  /// The robot's camera (camera.driver openni2 or v4l2, else std::runtime_error), with the GPIO
  /// trigger when camera.trigger_chip is set.
  static std::unique_ptr<LiveCamera> robot(const config::RobotConfig& cfg, rt::FramePool& pool,
                                           rt::SpscRing<rt::FrameHandle>& frames,
                                           const LiveCameraSeams& seams = {});
  /// An OpenNI2 camera with these settings and no trigger (`--through-drivers`: the clip).
  static std::unique_ptr<LiveCamera> openni2(const drivers::Openni2DriverSettings& settings,
                                             rt::FramePool& pool,
                                             rt::SpscRing<rt::FrameHandle>& frames);
  ~LiveCamera();
  LiveCamera(const LiveCamera&) = delete;
  LiveCamera& operator=(const LiveCamera&) = delete;

  /// The recorder's frame tap; set before start().
  void set_tap(rt::SpscRing<rt::FrameHandle>* tap) noexcept;
  /// The recorder's tap of the GPIO trigger's edges (full: the newest edge is dropped and counted
  /// in trigger_counters().tap_dropped); set before start(). Without a trigger: nothing.
  void set_edge_tap(rt::SpscRing<drivers::TriggerEdge>* tap) noexcept;
  /// Starts the trigger (if any), then the camera; throws naming the device, chip or line (and
  /// leaves neither running).
  void start();
  /// Stops and joins the camera's thread, then the trigger's. Idempotent.
  void stop();

  /// The OpenNI2 driver, or null (DriverReplay anchors its IMU to the clip's clock).
  [[nodiscard]] const drivers::Openni2Driver* openni2_driver() const noexcept {
    return openni2_.get();
  }
  [[nodiscard]] drivers::RgbdDriverCounters counters() const noexcept;
  /// Streams lost so far (counters().losses).
  [[nodiscard]] std::uint64_t losses() const noexcept;
  /// With the trigger: its edges, and how frames matched them.
  [[nodiscard]] bool triggered() const noexcept { return trigger_ != nullptr; }
  /// "chip:line" of the trigger ("" without one), as `vigs record` names the edges' source.
  [[nodiscard]] std::string trigger_source() const { return trigger_ ? trigger_->source() : ""; }
  [[nodiscard]] std::optional<drivers::GpioTriggerCounters> trigger_counters() const noexcept;
  [[nodiscard]] std::optional<drivers::TriggerMatchCounters> trigger_match_counters()
      const noexcept;

 private:
  LiveCamera() = default;

  std::unique_ptr<drivers::Openni2Driver> openni2_;
  std::unique_ptr<drivers::V4l2RgbdDriver> v4l2_;
  // Frame sync: the edges ring (gpio_trigger -> the camera driver's matcher), trigger, matcher.
  std::unique_ptr<rt::SpscRing<drivers::TriggerEdge>> edges_;
  std::unique_ptr<drivers::GpioTrigger> trigger_;
  std::unique_ptr<drivers::TriggerMatcher> matcher_;
  int trigger_event_fd_ = -1;
};

}  // namespace vigs::pipeline
