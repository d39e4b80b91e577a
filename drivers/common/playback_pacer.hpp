// PlaybackPacer: when a recorded frame is due on the host clock, so that a clip played in real
// time behaves as a sensor does: no frame is delivered before the time it stands for, and the
// schedule does not drift over minutes.
//
// Why not OpenNI2's own pacing (PlaybackControl::setSpeed(1))? Its player
// (Source/Drivers/OniFile/PlayerDevice.cpp, SleepToTimestamp) sleeps whole milliseconds, truncated,
// and takes the current frame as the new reference after every sleep, so the fraction lost on each
// frame is never made up: a 20 Hz clip plays about 1 % fast (measured: frames 630 ms ahead of
// their stamps after 60 s), and slower on a loaded machine. Against an IMU fed at the stamps'
// host times the tracker then sees frames whose IMU has not arrived yet. The driver therefore
// plays clips in OpenNI2's manual mode (one record per read) and holds each pair until due here.
//
// Schedule: the first frame anchors it (device time d0 at host h0); a frame of device time d is due
// at h0 + (d - d0) / speed. A frame that is already late is due now (no catching up by skipping:
// the reader's own backlog policy decides). The anchor is taken again when the device time goes
// back (the clip started over) or when a frame would be held longer than max_hold_ns (a gap in
// the recording: OpenNI2's player caps its sleeps the same way), and counted.
// Plain arithmetic: noexcept, no allocation, no clock reads (the caller passes now).
#pragma once

#include <cmath>
#include <cstdint>

namespace vigs::drivers {

class PlaybackPacer {
 public:
  /// speed: recorded seconds per host second (> 0); max_hold_ns: longest hold before re-anchoring.
  PlaybackPacer(double speed, std::int64_t max_hold_ns) noexcept
      : speed_(speed > 0.0 ? speed : 1.0), max_hold_ns_(max_hold_ns) {}

  /// Host time at which the frame of device time `t_device_ns` is due, read at host `now_ns`.
  [[nodiscard]] std::int64_t due_ns(std::int64_t t_device_ns, std::int64_t now_ns) noexcept {
    if (anchored_ && t_device_ns >= last_device_ns_) {
      const auto ahead_ns = static_cast<std::int64_t>(
          std::llround(static_cast<double>(t_device_ns - device0_ns_) / speed_));
      const std::int64_t due = host0_ns_ + ahead_ns;
      if (due - now_ns <= max_hold_ns_) {
        last_device_ns_ = t_device_ns;
        return due;
      }
    }
    if (anchored_) ++reanchors_;
    anchored_ = true;
    device0_ns_ = last_device_ns_ = t_device_ns;
    host0_ns_ = now_ns;
    return now_ns;
  }

  /// Times the schedule was anchored again (clip restart, gap longer than max_hold_ns).
  [[nodiscard]] std::uint64_t reanchors() const noexcept { return reanchors_; }
  /// Forget the anchor (a reopened device starts a new schedule; not counted).
  void reset() noexcept { anchored_ = false; }

 private:
  double speed_;
  std::int64_t max_hold_ns_;
  bool anchored_ = false;
  std::int64_t device0_ns_ = 0;
  std::int64_t host0_ns_ = 0;
  std::int64_t last_device_ns_ = 0;
  std::uint64_t reanchors_ = 0;
};

}  // namespace vigs::drivers
