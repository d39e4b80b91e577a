#pragma once
// PosePublisher: the DDS publisher role. It owns the participant, the DDS publisher and one
// writer per topic, and drains the tracker's pose ring on its own non-real-time thread (the
// thread table's `dds_pub`: SCHED_OTHER, every 2 ms). From each PoseSample it writes
//   <prefix>/pose          PoseWithCovarianceStamped (frame dds.map_frame_id)
//   <prefix>/pose_quality  vigs_msgs PoseQuality: the pose's header, source, flags, keyframe
//   <prefix>/odom          Odometry (child frame dds.camera_frame_id, twist in the camera frame)
//   rt/tf                  TFMessage map -> camera
//   <prefix>/keyframe      PoseStamped, only when sample.keyframe
// all stamped with the sample's sensor time t_ns, and, at 1 Hz, the newest StatusSnapshot (if
// one arrived since the last) on <prefix>/status.
//
// The producer never waits for DDS: it pushes into a lock-free ring (rt::SpscRing, full ->
// drop newest and count; or rt::OverwriteRing, full -> overwrite oldest and count) and only this
// thread calls Fast DDS. Writers keep a bounded KEEP_LAST history, so a write does not wait
// for a slow, stopped or absent reader either. Samples with a non-finite number are not
// published (counted in rejected). With dds.enabled false no participant is created and the
// thread drains and discards (counted), so the ring never fills.
//
// Lifecycle: construct (creates every entity, in order, each checked; throws DdsConfigError or
// std::runtime_error), start() (the thread), stop() (one last drain, then join; also in the
// destructor, before the entities are deleted).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "core/types/pose_sample.hpp"
#include "dds/dds_config.hpp"
#include "dds/status_snapshot.hpp"
#include "rt/overwrite_ring.hpp"
#include "rt/periodic_task.hpp"
#include "rt/spsc_ring.hpp"
#include "rt/thread_table.hpp"

namespace vigs::dds {

class PosePublisher {
 public:
  using PoseRing = rt::SpscRing<PoseSample>;
  using PoseOverwriteRing = rt::OverwriteRing<PoseSample>;
  using StatusMailbox = rt::OverwriteRing<StatusSnapshot>;  ///< capacity 1: latest value

  struct Stats {
    std::uint64_t poses_published = 0;      ///< samples written on pose, pose_quality, odom, tf
    std::uint64_t keyframes_published = 0;  ///< samples written on keyframe
    std::uint64_t status_published = 0;
    std::uint64_t rejected = 0;      ///< samples (or snapshots) with non-finite values or stamps
    std::uint64_t write_errors = 0;  ///< DataWriter::write returned false
    std::uint64_t discarded = 0;     ///< drained while dds.enabled is false
  };

  /// `status` may be null (no status topic traffic). `robot` goes into Status.robot.
  PosePublisher(const DdsConfig& config, PoseRing& poses, StatusMailbox* status = nullptr,
                std::string robot = {});
  PosePublisher(const DdsConfig& config, PoseOverwriteRing& poses, StatusMailbox* status = nullptr,
                std::string robot = {});
  ~PosePublisher();
  PosePublisher(const PosePublisher&) = delete;
  PosePublisher& operator=(const PosePublisher&) = delete;

  /// Starts the `dds_pub` thread as `spec` says (the pipeline passes the table's entry after
  /// its rt: policy, so `realtime_priorities: false` and `pin_cpus: false` reach it too). Once.
  void start(const rt::ThreadSpec& spec = rt::thread_spec("dds_pub"));
  /// Stops the thread after one last drain. Idempotent.
  void stop();

  /// One publisher cycle (drain the ring, and publish status if `now_ns` is a status period
  /// after the last one). The thread calls this; call it yourself only while not started.
  /// Returns the number of pose samples taken from the ring.
  std::size_t run_cycle(std::int64_t now_ns);

  /// Readers currently matched on <prefix>/pose (0 when disabled).
  [[nodiscard]] int pose_subscribers() const;
  /// Readers currently matched on <prefix>/pose_quality (0 when disabled).
  [[nodiscard]] int pose_quality_subscribers() const;
  /// Waits until every pose/odom/tf writer has at least `n` matched readers.
  bool wait_for_subscribers(int n, std::chrono::milliseconds timeout) const;

  /// Waits until every matched reliable reader acknowledged what was written (shutdown, tests).
  bool wait_for_acknowledgments(std::chrono::milliseconds timeout) const;

  [[nodiscard]] Stats stats() const noexcept;
  [[nodiscard]] bool enabled() const noexcept { return entities_ != nullptr; }
  /// The thread's statistics (cycle time, overruns), null before start().
  [[nodiscard]] const rt::PeriodicTask* task() const noexcept { return task_.get(); }

  static constexpr std::int64_t kStatusPeriodNs = 1'000'000'000;

 private:
  struct Entities;  // Fast DDS objects and reusable messages (pose_publisher.cpp)
  PosePublisher(const DdsConfig& config, std::function<bool(PoseSample&)> pop,
                StatusMailbox* status, std::string robot);
  void publish(const PoseSample& s);
  void publish_status(const StatusSnapshot& s);

  std::function<bool(PoseSample&)> pop_pose_;
  StatusMailbox* status_ = nullptr;
  std::string robot_;
  std::unique_ptr<Entities> entities_;
  std::int64_t last_status_ns_ = 0;
  bool status_started_ = false;
  std::atomic<std::uint64_t> poses_published_{0}, keyframes_published_{0}, status_published_{0},
      rejected_{0}, write_errors_{0}, discarded_{0};
  std::unique_ptr<rt::PeriodicTask> task_;
};

}  // namespace vigs::dds
