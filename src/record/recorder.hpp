// Recorder: the `recorder` thread of the thread table (SCHED_OTHER, 20 ms period). It drains its
// own tap ring from each driver into an MCAP file in the project's layout:
//   /vigs/rgb, /vigs/depth   sensor_msgs/Image (rgb8 or mono8; 16UC1 raw depth), one per pair
//   /vigs/camera_info        sensor_msgs/CameraInfo with each pair (the configured intrinsics)
//   /vigs/imu                sensor_msgs/Imu per stamped sample
//   /vigs/imu/serial         vigs_msgs/SerialChunk: the port's raw bytes, exactly as read
//   /vigs/camera/trigger     sensor_msgs/TimeReference per GPIO frame-sync edge
//   /vigs/pose               geometry_msgs/PoseStamped per tracked frame (`vigs run --record`)
//   /vigs/pose/imu_used      sensor_msgs/TimeReference: the newest IMU sample that frame used
// (the topics of vigs simulate and vigs replay; tests/record checks them against src/eval's).
// Log time = the sample's own t_ns (CLOCK_MONOTONIC), so messages of a stream are in order.
//
// Taps: each driver pushes into the recorder's ring with drop-newest-and-count (the driver's
// tap_* counters); a slow disk never slows a driver. The recorder holds a frame slot only while
// it encodes it. Crash safety is McapWriter's: chunks (zstd, default level 3) are written as soon
// as they are full or span 1 s, in place, so a SIGKILL leaves a file readable to its last
// chunk; stop() drains every tap and writes the summary. A write error (disk full) stops
// recording: error() names the file, the taps then fill and their drivers count the drops.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/types/imu_sample.hpp"
#include "core/types/pose_sample.hpp"
#include "drivers/common/trigger_edge.hpp"
#include "drivers/serial_imu/serial_bytes.hpp"
#include "io/mcap/mcap_writer.hpp"
#include "io/recording_topics.hpp"
#include "rt/frame_pool.hpp"
#include "rt/periodic_task.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::record {

// The topics are declared once, in io/recording_topics.hpp.
inline constexpr const char* kRgbTopic = io::topics::kRgb.name.data();
inline constexpr const char* kDepthTopic = io::topics::kDepth.name.data();
inline constexpr const char* kCameraInfoTopic = io::topics::kCameraInfo.name.data();
inline constexpr const char* kImuTopic = io::topics::kImu.name.data();
inline constexpr const char* kSerialTopic = io::topics::kImuSerial.name.data();
inline constexpr const char* kTriggerTopic = io::topics::kCameraTrigger.name.data();
inline constexpr const char* kPoseTopic = io::topics::kPose.name.data();
inline constexpr const char* kTrackerImuTopic = io::topics::kTrackerImu.name.data();

/// One tracked frame's pose and the stamp of the newest IMU sample the tracker had used for it.
struct RecordedPose {
  PoseSample pose;
  std::int64_t imu_t_ns = 0;
};

struct CameraIntrinsics {
  double fx_px = 0, fy_px = 0, cx_px = 0, cy_px = 0;
};

struct RecorderStats {
  std::uint64_t frames = 0;  // RGB-D pairs written
  std::uint64_t imu_samples = 0;
  std::uint64_t serial_chunks = 0;
  std::uint64_t serial_bytes = 0;
  std::uint64_t edges = 0;
  std::uint64_t poses = 0;
  std::uint64_t bytes_written = 0;  // file size so far
  std::uint64_t chunks = 0;
};

class Recorder {
 public:
  /// Creates (truncates) nothing yet; start() opens the file.
  explicit Recorder(std::string path, io::mcap::McapWriterOptions options = {});
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Taps, before start(). Each ring's only consumer is the recorder.
  void add_frames(rt::FramePool& pool, rt::SpscRing<rt::FrameHandle>& tap,
                  const CameraIntrinsics& intrinsics);
  void add_imu(rt::SpscRing<ImuSample>& tap);
  void add_serial(rt::SpscRing<drivers::SerialBytes>& tap, std::string port);
  void add_edges(rt::SpscRing<drivers::TriggerEdge>& tap, std::string source);
  /// The tracker's poses (T_w_c, stamped at their frame), in `frame_id` (the map frame).
  void add_poses(rt::SpscRing<RecordedPose>& tap, std::string frame_id);

  /// Opens the file (throws io::IoError naming it) and starts the recorder thread.
  void start();
  /// Opens the file without a thread: the caller drains (benchmarks, lockstep use).
  void open();
  /// Stops the thread, drains every tap, writes the summary and closes the file. Throws
  /// io::IoError if the file could not be completed. Idempotent.
  void stop();
  /// One drain of every tap on the caller's thread (what each recorder tick does).
  void drain_once();

  /// Snapshot, any thread.
  [[nodiscard]] RecorderStats stats() const noexcept;
  /// Non-empty once a write failed (the message names the file).
  [[nodiscard]] std::string error() const;
  [[nodiscard]] const std::string& path() const noexcept { return path_; }

 private:
  struct Channels;
  void write_frame(rt::FrameHandle h);

  std::string path_;
  io::mcap::McapWriterOptions options_;
  std::unique_ptr<io::mcap::McapWriter> writer_;
  std::unique_ptr<Channels> ch_;
  rt::FramePool* pool_ = nullptr;
  rt::SpscRing<rt::FrameHandle>* frames_ = nullptr;
  CameraIntrinsics intrinsics_;
  rt::SpscRing<ImuSample>* imu_ = nullptr;
  rt::SpscRing<drivers::SerialBytes>* serial_ = nullptr;
  std::string serial_port_;
  rt::SpscRing<drivers::TriggerEdge>* edges_ = nullptr;
  std::string edge_source_;
  rt::SpscRing<RecordedPose>* poses_ = nullptr;
  std::string pose_frame_id_;
  std::optional<rt::PeriodicTask> task_;
  std::atomic<bool> failed_{false};
  mutable std::mutex error_mutex_;  // error_ only; never taken by a driver
  std::string error_;
  std::atomic<std::uint64_t> frames_n_{0}, imu_n_{0}, chunks_n_{0}, serial_bytes_n_{0}, edges_n_{0},
      poses_n_{0}, bytes_written_{0}, mcap_chunks_{0};
};

}  // namespace vigs::record
