#pragma once
// DriverReplay: `vigs run --source replay:F.mcap --through-drivers`. A recording presented to
// the live pipeline through the REAL drivers, exactly as `--source live` presents sensors:
//  - camera: the recording's colour + depth pairs become an .oni clip (io/oni/mcap_to_oni.hpp,
//    frame timestamps = the recorded stamps) that the real Openni2Driver plays through real
//    OpenNI2 in real time (playback_speed 1: the driver paces the frames). The clip is cached
//    next to the recording (F.mcap -> F.drivers.oni, rebuilt when older than the recording),
//    or, when that folder is not writable or the run needs its own clip, in a temporary
//    folder removed by the destructor;
//  - IMU: every recorded sample is encoded as an Xsens MTData2 message (SampleTimeFine = 10 kHz
//    ticks of recording time) and written into a pseudo-terminal whose slave the real
//    SerialImuDriver reads, paced by its stamp on a feeder thread.
//
// Time. The drivers stamp in the host clock (CLOCK_MONOTONIC) and the evaluation needs the
// recording's. The camera leads: the OpenNI2 driver anchors its DeviceClock on the first frame
// it reads (host = device time + host_minus_device). A clip frame recorded at t has device time
// d(t) = 1 ms + (t - t_first_frame), so it is stamped host(t) = host_minus_device + d(t). The
// feeder waits for that anchor and then writes the IMU sample recorded at t at host(t), so both
// drivers see one clock and the IMU driver's stamps (its clock fit: write time + the pty's
// latency) line up with the frames'. host_minus_recording_ns() = host(t) - t: subtracting it
// maps a pose stamp back to the recording's clock (the RESULTS_DIR is written in it, so `vigs
// eval run --gt F.mcap` works). Samples whose host(t) has already passed when the anchor is
// known (those recorded up to the first frame) are written at once and counted (late_samples).
// The anchor is read once: a camera that is lost and reopened re-anchors its stamps (by the
// reopen latency), and frames after that stay shifted against the IMU by as much.
//
// Faults (tests, DriverReplayFaults): the IMU goes silent for a while (its samples in the window
// are never written: the stream stops and resumes, the driver counts a counter gap); one byte of
// every Nth message flipped, from a given time on (the parser rejects the checksum and resyncs,
// counted); the camera disappears (its clip is cut inside a frame, so OpenNI2's playback stalls
// and the driver's frame watchdog loses the device; the path is removed then, so reopening fails
// as for an unplugged camera) and returns (a clip of the later frames is renamed onto the path;
// the driver reopens it with its backoff and plays on).
#include <atomic>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/types/imu_sample.hpp"
#include "core/types/pinhole_camera.hpp"
#include "drivers/serial_imu/pseudo_terminal.hpp"
#include "rt/counters.hpp"
#include "rt/rt_thread.hpp"

namespace vigs::drivers {
class Openni2Driver;
}

namespace vigs::pipeline {

struct DriverReplayFaults {
  std::int64_t imu_pause_at_ns = -1;  ///< recording time after the first frame; < 0: never
  std::int64_t imu_pause_ns = 0;      ///< the IMU sends nothing for this long
  int corrupt_every = 0;              ///< flip one byte of every Nth IMU message; 0: none
  /// Recording time after the first frame from which messages are counted for corrupt_every
  /// (the default: every message, also those recorded before the first frame).
  std::int64_t corrupt_from_ns = std::numeric_limits<std::int64_t>::min();
  std::int64_t camera_gone_at_ns = -1;  ///< recording time after the first frame; < 0: never
  std::int64_t camera_gone_ns = 0;      ///< the camera returns with the frame this much later
  [[nodiscard]] bool camera_gone() const noexcept { return camera_gone_at_ns >= 0; }
};

struct DriverReplaySettings {
  std::string recording;
  std::int64_t max_frames = 0;  ///< 0 = all (else the clip is the run's own, in a temp folder)
  DriverReplayFaults faults;
  rt::ThreadSpec feeder_thread;  ///< the table's sensor_replay entry with the rt policy applied
  std::int64_t anchor_timeout_ns = 20'000'000'000;  ///< give up waiting for the first frame
};

struct DriverReplayCounters {
  std::uint64_t imu_samples_written = 0;
  std::uint64_t imu_samples_withheld = 0;  ///< the IMU pause
  std::uint64_t imu_messages_corrupted = 0;
  std::uint64_t late_samples = 0;  ///< written after their time (before the camera's anchor)
  std::uint64_t camera_returns = 0;
};

class DriverReplay {
 public:
  /// Makes (or reuses) the clip, reads the IMU samples, opens the pty. Throws naming the file.
  explicit DriverReplay(const DriverReplaySettings& settings);
  ~DriverReplay();  // stops the feeder; removes the temporary folder
  DriverReplay(const DriverReplay&) = delete;
  DriverReplay& operator=(const DriverReplay&) = delete;

  /// Where the clip of `recording` is cached, and whether it is there and newer than it.
  [[nodiscard]] static std::string cached_clip_path(const std::string& recording);
  [[nodiscard]] static bool clip_cached(const std::string& recording);

  [[nodiscard]] const std::string& clip_path() const noexcept { return clip_path_; }
  [[nodiscard]] const std::string& imu_port() const noexcept { return pty_.slave_path(); }
  [[nodiscard]] const PinholeCamera& camera() const noexcept { return camera_; }
  [[nodiscard]] double imu_rate_hz() const noexcept { return imu_rate_hz_; }

  /// Starts the feeder: it waits for `camera`'s clock anchor, then writes the IMU (and swaps
  /// the camera's clip for the camera fault). `camera` must outlive stop().
  void start(const drivers::Openni2Driver& camera);
  void stop();
  /// The camera's clip has ended: lets the feeder write the IMU's last samples (the ones past
  /// the last frame's arrival) for at most `within_ns`, then stops it.
  void finish(std::int64_t within_ns);
  /// The feeder wrote (or withheld) every IMU sample.
  [[nodiscard]] bool done() const noexcept { return done_.load(std::memory_order_acquire); }

  /// Host CLOCK_MONOTONIC minus recording time, once the camera has anchored.
  [[nodiscard]] std::optional<std::int64_t> host_minus_recording_ns() const noexcept;
  /// The feeder gave up (no camera frame within anchor_timeout_ns) or a write failed.
  [[nodiscard]] bool failed() const noexcept { return failed_.load(std::memory_order_acquire); }
  /// Why, once failed(); empty otherwise.
  [[nodiscard]] std::string error() const;
  [[nodiscard]] DriverReplayCounters counters() const noexcept;

 private:
  void run(const std::stop_token& stop, const drivers::Openni2Driver& camera);
  void make_clips();

  DriverReplaySettings s_;
  PinholeCamera camera_;
  std::int64_t first_frame_t_ns_ = 0;
  double imu_rate_hz_ = 200;
  std::vector<ImuSample> imu_;
  std::string clip_path_;
  std::string return_clip_path_;  // camera fault: renamed over clip_path_ when it returns
  std::int64_t return_t_ns_ = 0;  // recording stamp of the returning clip's first frame
  std::string temp_dir_;          // removed by the destructor
  drivers::PseudoTerminal pty_;
  std::atomic<std::int64_t> host_minus_recording_ns_{INT64_MIN};
  std::atomic<bool> failed_{false};
  std::atomic<bool> done_{false};
  std::string error_;  // written by the feeder before failed_
  rt::SingleWriterCounter written_, withheld_, corrupted_, late_, returns_;
  std::optional<rt::RtThread> thread_;
};

}  // namespace vigs::pipeline
