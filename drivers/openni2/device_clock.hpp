// DeviceClock: device timestamps (OpenNI2: microseconds since the device or clip started) to host
// CLOCK_MONOTONIC nanoseconds (rt/clock.hpp), kept deliberately simple.
//
// The first frame anchors the map: offset = host time when that frame was read - its device
// time. Every later frame is stamped device time + offset, so stamps keep the device's own
// spacing (no read jitter) and playback of a clip keeps its recorded spacing. If the device time
// goes backwards (device reset, clip restarting) the map re-anchors on that frame and counts it.
// Stamps are forced strictly increasing (at least 1 ns apart), so consumers may rely on order.
// Limits: no drift estimate (a device clock that runs fast or slow against the host slowly moves
// the stamps away from host time; a few ppm on real sensors), and the anchor includes the first
// frame's transfer latency. noexcept and allocation-free.
#pragma once

#include <cstdint>

namespace vigs::drivers {

class DeviceClock {
 public:
  // Host stamp for a frame with device time `t_device_us`, read at host time `t_host_read_ns`.
  [[nodiscard]] std::int64_t to_host_ns(std::int64_t t_device_us,
                                        std::int64_t t_host_read_ns) noexcept {
    const std::int64_t t_device_ns = t_device_us * 1000;
    if (!anchored_ || t_device_us < last_device_us_) {
      if (anchored_) ++reanchors_;
      offset_ns_ = t_host_read_ns - t_device_ns;
      anchored_ = true;
    }
    last_device_us_ = t_device_us;
    std::int64_t t_ns = t_device_ns + offset_ns_;
    if (have_last_ && t_ns <= last_host_ns_) t_ns = last_host_ns_ + 1;
    last_host_ns_ = t_ns;
    have_last_ = true;
    return t_ns;
  }

  // Host minus device time of the current anchor, ns (0 before the first frame).
  [[nodiscard]] std::int64_t offset_ns() const noexcept { return offset_ns_; }
  // Times the device clock went backwards and the map was re-anchored.
  [[nodiscard]] std::uint64_t reanchors() const noexcept { return reanchors_; }
  void reset() noexcept { *this = DeviceClock{}; }

 private:
  bool anchored_ = false;
  bool have_last_ = false;
  std::int64_t offset_ns_ = 0;
  std::int64_t last_device_us_ = 0;
  std::int64_t last_host_ns_ = 0;
  std::uint64_t reanchors_ = 0;
};

}  // namespace vigs::drivers
