#include "pipeline/live_tracker.hpp"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>

#include "pipeline/pool_frame_view.hpp"
#include "pipeline/pose_quality.hpp"
#include "rt/clock.hpp"

namespace vigs::pipeline {
namespace {

constexpr std::size_t kEarlyImuSamples = 4096;  // IMU samples kept before the first frame
// A frame whose newest IMU sample is older than this has no IMU of its own (the stream stopped).
constexpr std::int64_t kImuStaleNs = 100'000'000;
// How long a frame waits at most for the IMU to deliver a sample after its stamp: two IMU
// periods at 200 Hz (the IMU thread, late under load, usually needs well under 1 ms). Longer
// waits come out of the pose latency and the tracker's period: with 50 ms, through the drivers
// (OpenNI2's player runs ahead of the IMU feeder's stamps) the tick took 52-60 ms at p50
// against 27 ms of tracking, and 120 of 201 frames were tracked instead of ~180. A frame that
// times out is tracked with the IMU it has (extrapolated to its stamp) and counted (imu_late).
constexpr std::int64_t kImuCoverNs = 10'000'000;

PoseSample pose_sample(const TrackedFrame& f, std::uint64_t index, std::uint32_t flags,
                       const Odometry& odometry) {
  PoseSample p = tracked_pose(f, index);
  if (f.covariance_valid) std::memcpy(p.covariance, f.covariance, sizeof(p.covariance));
  if (odometry.guess_mode() == tracking::InitialGuessMode::imu) {
    const Eigen::Vector3d& v = odometry.inertial().velocity_w_mps();
    for (int i = 0; i < 3; ++i) p.v_w_mps[i] = v[i];
  }
  p.source = pose_source(f, index);
  p.keyframe = f.keyframe;
  p.flags = flags | frame_pose_flags(f);  // degenerate, map restarted
  return p;
}

}  // namespace

PoseSample tracked_pose(const TrackedFrame& f, std::uint64_t index) {
  PoseSample p;
  p.t_ns = f.t_ns;
  p.frame_index = index;
  const Eigen::Vector3d t = f.T_w_c.translation();
  const Eigen::Quaterniond q(f.T_w_c.rotation());
  for (int i = 0; i < 3; ++i) p.p_w_m[i] = t[i];
  p.q_w_xyzw[0] = q.x();
  p.q_w_xyzw[1] = q.y();
  p.q_w_xyzw[2] = q.z();
  p.q_w_xyzw[3] = q.w();
  return p;
}

LiveTracker::LiveTracker(const config::RobotConfig& cfg, const LiveTrackerSettings& settings,
                         const LiveTrackerRings& rings)
    : cfg_(cfg), s_(settings), r_(rings), phase_lock_(settings.phase_lock) {
  early_imu_.reserve(kEarlyImuSamples);
}

template <class Pred>
bool LiveTracker::wait(Pred&& ready, const char* what) noexcept {
  if (ready()) return true;
  if (!s_.lockstep) return false;
  const std::int64_t give_up = rt::monotonic_ns() + s_.wait_timeout_ns;
  while (!ready()) {
    if (rt::monotonic_ns() > give_up) {
      std::snprintf(failure_, sizeof(failure_),
                    "lockstep: the tracker waited %.1f s for %s (nothing moved)",
                    rt::ns_to_s(s_.wait_timeout_ns), what);
      failed_.store(true, std::memory_order_release);
      return false;
    }
    rt::sleep_until_ns(rt::monotonic_ns() + 100'000);
  }
  return true;
}

bool LiveTracker::take_frame(rt::FrameHandle& h) noexcept {
  if (end_pending_) {  // the frame before the end marker was tracked last tick
    h = rt::FrameHandle{};
    return true;
  }
  if (s_.lockstep) return r_.frames.try_pop(h);
  if (!r_.frames.try_pop(h)) return false;
  rt::FrameHandle newer;
  // Skip to the newest frame. The end marker ends the skipping: the frame before it is tracked.
  while (h.valid() && r_.frames.try_pop(newer)) {
    if (!newer.valid()) {
      end_pending_ = true;
      break;
    }
    r_.pool.release(h);
    skipped_.add();
    pending_flags_ |= kPoseFlagFramesSkipped;
    h = newer;
  }
  return true;
}

std::int64_t LiveTracker::tick(std::int64_t wake_ns) {
  if (done() || failed()) return 0;
  rt::FrameHandle h;
  while (take_frame(h)) {
    if (!h.valid()) {
      finish();
      return 0;
    }
    // Read before process() releases the slot.
    const std::int64_t arrival_ns = r_.pool.frame(h).arrival_ns;
    process(h, wake_ns);
    if (failed()) return 0;
    if (!s_.lockstep) {
      const bool locking = s_.phase_lock.period_ns > 0 && wake_ns > 0 && arrival_ns > 0;
      return locking ? phase_lock_.shift_ns(wake_ns, arrival_ns) : 0;
    }
  }
  return 0;
}

void LiveTracker::feed_imu(std::int64_t t_ns) noexcept {
  for (; early_fed_ < early_imu_.size() && early_imu_[early_fed_].t_ns <= t_ns; ++early_fed_) {
    imu_samples_.add();
    if (!odometry_->add_imu(early_imu_[early_fed_])) imu_refused_.add();
    last_imu_t_ns_ = early_imu_[early_fed_].t_ns;
  }
  while (const ImuSample* s = r_.imu.front()) {
    if (s->t_ns > t_ns) break;
    imu_samples_.add();
    if (!odometry_->add_imu(*s)) imu_refused_.add();
    last_imu_t_ns_ = s->t_ns;
    r_.imu.pop();
  }
}

void LiveTracker::gather_early_imu(std::int64_t t_ns) noexcept {
  while (const ImuSample* s = r_.imu.front()) {
    if (s->t_ns > t_ns || early_imu_.size() == early_imu_.capacity()) break;
    early_imu_.push_back(*s);  // reserved: never allocates
    r_.imu.pop();
  }
}

void LiveTracker::await_imu(std::int64_t t_ns) noexcept {
  const std::int64_t give_up = rt::monotonic_ns() + kImuCoverNs;
  for (;;) {
    if (odometry_) {
      feed_imu(t_ns);
    } else {
      gather_early_imu(t_ns);
    }
    const ImuSample* next = r_.imu.front();
    if (next != nullptr && next->t_ns > t_ns) return;  // the IMU has passed the frame
    const std::int64_t newest =
        odometry_ ? last_imu_t_ns_ : (early_imu_.empty() ? INT64_MIN : early_imu_.back().t_ns);
    if (next != nullptr || newest < t_ns - kImuStaleNs) return;  // full, or stopped: flagged
    if (rt::monotonic_ns() > give_up) {
      imu_late_.add();
      return;
    }
    rt::sleep_until_ns(rt::monotonic_ns() + 100'000);
  }
}

bool LiveTracker::start_odometry(std::int64_t t_ns) {
  // Gather samples up to the frame (and, without enough there, wait for the next ones).
  gather_early_imu(t_ns);
  const bool imu_mode = s_.odometry.guess
                            ? *s_.odometry.guess == tracking::InitialGuessMode::imu
                            : cfg_.tracking.initial_guess == tracking::InitialGuessMode::imu;
  if (imu_mode) {
    // initial_camera_pose() levels the frame from kMinRestSamples in its rest window; when the
    // IMU did not run that long before the frame, wait (lockstep) for the rest after it.
    std::size_t in_window = 0;
    for (const ImuSample& s : early_imu_) in_window += s.t_ns >= t_ns - kRestWindowNs;
    const auto enough = [&] {
      while (in_window < kMinRestSamples && early_imu_.size() < early_imu_.capacity()) {
        ImuSample s;
        if (!r_.imu.try_pop(s)) return false;
        early_imu_.push_back(s);
        in_window += s.t_ns >= t_ns - kRestWindowNs;
      }
      return true;
    };
    if (!wait(enough, "the first IMU samples (imu ring)")) return false;
  }
  RecordedMotion motion;
  motion.imu = early_imu_;
  OdometryOptions opt = s_.odometry;
  if (!opt.initial_T_w_c)
    opt.initial_T_w_c =
        initial_camera_pose(motion, t_ns, cfg_, initial_pose_, InitialPoseSource::gravity);
  odometry_.emplace(cfg_, s_.camera, opt);
  if (r_.keyframes != nullptr)
    held_frames_.emplace(
        std::bit_ceil(std::max<std::size_t>(1, odometry_->tracker().held_capacity())));
  return true;
}

void LiveTracker::process(rt::FrameHandle h, std::int64_t wake_ns) noexcept {
  const rt::Frame& frame = r_.pool.frame(h);
  const std::int64_t t_ns = frame.t_ns;
  if (t_ns <= last_t_ns_) {
    r_.pool.release(h);
    out_of_order_.add();
    pending_flags_ |= kPoseFlagOutOfOrder;
    return;
  }
  try {
    if (!s_.lockstep) await_imu(t_ns);
    if (!odometry_ && !start_odometry(t_ns)) {
      r_.pool.release(h);
      if (!failed()) waiting_imu_.add();
      return;
    }
  } catch (...) {  // start-up only: an Odometry that cannot be built is a configuration error
    std::snprintf(failure_, sizeof(failure_), "the tracker could not start its odometry");
    failed_.store(true, std::memory_order_release);
    r_.pool.release(h);
    return;
  }
  last_t_ns_ = t_ns;
  feed_imu(t_ns);
  const RgbdView view = pool_frame_view(frame, r_.pool.settings(), s_.depth_scale_m);
  const std::int64_t t0 = rt::monotonic_ns();
  const TrackedFrame f = odometry_->track(view);
  const std::int64_t t1 = rt::monotonic_ns();
  std::uint32_t flags = pending_flags_ | driver_fault_flags();
  pending_flags_ = 0;
  // No prediction, or one the IMU stream stopped short of (the frontend then extrapolates the
  // last reading): flagged and counted.
  if (odometry_->guess_mode() == tracking::InitialGuessMode::imu && frame_index_ > 0 &&
      (!f.imu_guess || last_imu_t_ns_ < t_ns - kImuStaleNs)) {
    flags |= kPoseFlagImuUnavailable;
    imu_unavailable_.add();
  }
  const PoseSample pose = pose_sample(f, frame_index_, flags, *odometry_);
  if (!wait([&] { return r_.poses.try_push(pose); }, "the publisher (pose ring)"))
    pose_drops_.add();
  LiveFrameResult result{
      f,          t1 - t0, rt::monotonic_ns(), frame.arrival_ns, s_.lockstep ? 0 : wake_ns,
      pose.flags, false,   last_imu_t_ns_};
  if (!wait([&] { return r_.results.try_push(result); }, "the main thread (result ring)"))
    result_drops_.add();
  if (r_.keyframes != nullptr) hand_keyframe(f, h);
  r_.pool.release(h);
  frames_.add();
  ++frame_index_;
}

std::uint32_t LiveTracker::driver_fault_flags() noexcept {
  if (s_.driver_faults == nullptr) return 0;
  std::uint32_t flags = 0;
  const std::uint64_t imu_corrupt = s_.driver_faults->imu_corrupt();
  if (!driver_faults_baseline_) {
    // The counts at the first pose are the baseline, not a fault: a serial port opened while
    // the IMU streams skips bytes to its first header (counted as resync) before any pose.
    driver_faults_baseline_ = true;
    imu_corrupt_seen_ = imu_corrupt;
    camera_losses_seen_ = s_.driver_faults->camera_losses();
    return 0;
  }
  if (imu_corrupt != imu_corrupt_seen_) flags |= kPoseFlagImuCorrupt;
  imu_corrupt_seen_ = imu_corrupt;
  const std::uint64_t camera_losses = s_.driver_faults->camera_losses();
  if (camera_losses != camera_losses_seen_) flags |= kPoseFlagCameraReopened;
  camera_losses_seen_ = camera_losses;
  return flags;
}

void LiveTracker::hand_keyframe(const TrackedFrame& f, rt::FrameHandle h) noexcept {
  if (f.reinitialized) release_held_frames();  // the tracker dropped the keyframes it held
  if (f.keyframe) {
    const tracking::Keyframe& kf = odometry_->tracker().last_keyframe();
    // The keyframe's own frame: this one (made at once), or the oldest kept one (released
    // moving_window_frames frames after it; the tracker releases its held keyframes in order).
    rt::FrameHandle own = h;
    if (kf.t_ns == f.t_ns || !held_frames_->try_pop(own)) r_.pool.retain(h);
    KeyframeSlot* slot = nullptr;
    if (r_.pool.frame(own).t_ns == kf.t_ns &&
        wait([&] { return (slot = r_.keyframes->acquire()) != nullptr; },
             "the mapper (keyframe slots)")) {
      slot->keyframe = kf;  // reuses the slot's capacity
      slot->frame = own;    // the retain above, or the one taken when the keyframe was held
      slot->after_restart = f.reinitialized;
      r_.keyframes->publish(slot);
      keyframes_.add();
    } else {  // no slot free (or, never expected, not the keyframe's frame): drop, counted
      r_.pool.release(own);
      r_.keyframes->count_drop();
    }
  }
  if (f.held && held_frames_->try_push(h)) r_.pool.retain(h);
}

void LiveTracker::release_held_frames() noexcept {
  rt::FrameHandle held;
  while (held_frames_ && held_frames_->try_pop(held)) r_.pool.release(held);
}

void LiveTracker::finish() noexcept {
  release_held_frames();  // keyframes the stream ended before are not published
  LiveFrameResult end;
  end.end_of_stream = true;
  // End markers are never dropped: retry until there is room (bounded in every mode).
  const bool lockstep = s_.lockstep;
  s_.lockstep = true;
  bool ok = wait([&] { return r_.results.try_push(end); }, "the main thread (result ring)");
  if (ok && r_.keyframes != nullptr)
    ok = wait([&] { return r_.keyframes->publish_end(); }, "the mapper (keyframe queue)");
  s_.lockstep = lockstep;
  if (ok) done_.store(true, std::memory_order_release);
}

LiveTrackerCounters LiveTracker::counters() const noexcept {
  LiveTrackerCounters c;
  c.frames = frames_.get();
  c.skipped = skipped_.get();
  c.waiting_imu = waiting_imu_.get();
  c.out_of_order = out_of_order_.get();
  c.imu_samples = imu_samples_.get();
  c.imu_refused = imu_refused_.get();
  c.imu_unavailable = imu_unavailable_.get();
  c.imu_late = imu_late_.get();
  c.pose_drops = pose_drops_.get();
  c.result_drops = result_drops_.get();
  c.keyframes = keyframes_.get();
  c.keyframe_drops = r_.keyframes != nullptr ? r_.keyframes->dropped() : 0;
  return c;
}

OdometryCounters LiveTracker::odometry_counters() const {
  return odometry_ ? odometry_->counters() : OdometryCounters{};
}

const rt::RtThread* LiveTracker::team_worker() const {
  if (!odometry_ || odometry_->tracker().team().size() < 2) return nullptr;
  return &odometry_->tracker().team().worker(1);
}

}  // namespace vigs::pipeline
