// The live pipeline's spine (see live_pipeline.hpp): build, start, run, drain, join.
#include "pipeline/live_pipeline.hpp"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

#include "dds/dds_config.hpp"
#include "dds/pose_publisher.hpp"
#include "drivers/common/trigger_edge.hpp"
#include "drivers/serial_imu/serial_imu_driver.hpp"
#include "pipeline/live_camera.hpp"
#include "pipeline/live_mapper.hpp"
#include "pipeline/live_status.hpp"
#include "pipeline/replay_figures.hpp"
#include "pipeline/steady_rate.hpp"
#include "rt/clock.hpp"
#include "rt/periodic_task.hpp"
#include "rt/poll.hpp"

namespace vigs::pipeline {
namespace {

constexpr std::size_t kKeyframeSlots = 2;
constexpr std::size_t kPoseRing = 256;
constexpr std::size_t kResultRing = 1024;

// --record: the recorder's own taps (pool slots are added for the frame tap, so a slow disk
// never takes a slot the driver or the tracker needs).
constexpr std::uint32_t kFrameTap = 16;
struct RecordTaps {
  rt::SpscRing<rt::FrameHandle> frames{kFrameTap};
  rt::SpscRing<ImuSample> imu{4096};
  rt::SpscRing<drivers::SerialBytes> bytes{1024};
  rt::SpscRing<record::RecordedPose> poses{kPoseRing};  // the main thread fills it (results)
  rt::SpscRing<drivers::TriggerEdge> edges{256};  // the GPIO trigger's, as `vigs record` taps them
  std::uint64_t pose_drops = 0;
};

record::RecordedPose recorded_pose(const LiveFrameResult& r, std::uint64_t index) {
  record::RecordedPose rp;
  rp.imu_t_ns = r.imu_t_ns;
  rp.pose = tracked_pose(r.frame, index);
  return rp;
}

// The drivers' fault totals the tracker flags its poses with (DriverFaultCounts): relaxed
// snapshots of their counters (noexcept, no allocation or lock), read on the tracker thread.
class DriverFaultTotals final : public DriverFaultCounts {
 public:
  DriverFaultTotals(const LiveCamera* camera, const drivers::SerialImuDriver* imu) noexcept
      : camera_(camera), imu_(imu) {}
  [[nodiscard]] std::uint64_t imu_corrupt() const noexcept override {
    if (imu_ == nullptr) return 0;
    const drivers::SerialImuFaults f = imu_->faults();
    return f.bad_checksum + f.resync_bytes_skipped + f.oversize_length + f.malformed_payload;
  }
  [[nodiscard]] std::uint64_t camera_losses() const noexcept override {
    return camera_ != nullptr ? camera_->losses() : 0;
  }

 private:
  const LiveCamera* camera_;
  const drivers::SerialImuDriver* imu_;
};

rt::ThreadSpec table_spec(const char* name, const config::RtSettings& rt) {
  return rt::apply_policy(rt::thread_spec(name), rt.realtime_priorities, rt.pin_cpus);
}

/// p50 and p99 (nearest rank) of ns; zeros when empty.
LatencyQuantiles quantiles(const std::vector<std::int64_t>& ns) {
  LatencyQuantiles q;
  if (ns.empty()) return q;
  q.p50_ns = *nearest_rank_quantile(ns, 0.5);
  q.p99_ns = *nearest_rank_quantile(ns, 0.99);
  q.count = ns.size();
  return q;
}

std::int64_t period_ns(double rate_hz) {
  return std::llround(1e9 / rate_hz);
}

}  // namespace

LiveResult run_live(const config::RobotConfig& cfg, const LiveOptions& o,
                    const std::function<void(const LiveProgress&)>& progress) {
  const config::RtSettings& rtc = cfg.rt;
  LiveResult out;

  // 1. Memory: lock it (rt.lock_memory) before any pool or ring exists.
  out.memory_lock = "not requested";
  if (rtc.lock_memory) out.memory_lock = std::string(rt::to_string(rt::lock_memory().result));

  // 2. Pool and rings, all allocated here.
  // The camera: the recording's, or the robot's (camera.*).
  PinholeCamera camera = o.recording.empty() ? PinholeCamera::from_settings(cfg.camera)
                                             : RecordingSource::first_camera(o.recording);
  const auto slots = static_cast<std::uint32_t>(rtc.frame_pool_slots);
  const bool record = !o.record_path.empty();
  if (record && !o.recording.empty() && !o.through_drivers)
    throw std::runtime_error(
        "--record records the drivers: it needs --source live or a recording played through "
        "the drivers (--through-drivers, the default source), not one played into the rings");
  const rt::FramePoolSettings pool_settings{.slots = slots + (record ? kFrameTap : 0),
                                            .width = static_cast<std::uint32_t>(camera.width_px),
                                            .height = static_cast<std::uint32_t>(camera.height_px),
                                            .colour_channels = 3};
  // Driver filling 1 + tracker 1 + keyframes in the mapper's hands + the frames of keyframes
  // the tracker holds for its moving test (kept for the mapper): the rest may be queued.
  const std::size_t reserved =
      2 +
      (o.mapping ? kKeyframeSlots + static_cast<std::size_t>(cfg.tracking.held_keyframes()) : 0);
  if (slots < reserved + 1)
    throw std::runtime_error("rt.frame_pool_slots " + std::to_string(slots) + " is below " +
                             std::to_string(reserved + 1) +
                             " (driver, tracker, keyframes, held keyframes' frames, ring)");
  rt::FramePool pool(pool_settings);
  rt::SpscRing<rt::FrameHandle> frames(std::bit_floor(slots - reserved));
  rt::SpscRing<ImuSample> imu(static_cast<std::size_t>(rtc.imu_ring_capacity));
  rt::SpscRing<PoseSample> poses(kPoseRing);
  rt::SpscRing<LiveFrameResult> results(kResultRing);
  std::optional<KeyframeHandoff> handoff;
  std::unique_ptr<RecordTaps> taps;
  std::unique_ptr<record::Recorder> recorder;
  const std::string record_partial = o.record_path + ".partial";
  if (record) {
    taps = std::make_unique<RecordTaps>();
    recorder = std::make_unique<record::Recorder>(record_partial);
  }
  // The drivers' pool holds OpenNI2's millimetres (an .oni clip's too).
  const float depth_scale_m =
      o.through_drivers ? 0.001f : static_cast<float>(cfg.camera.depth_scale_m);

  // 3. Sources: a recording played into the rings; the robot's drivers; or the recording
  // through those same drivers (DriverReplay: an .oni clip and a pty stand in for the sensors).
  std::unique_ptr<RecordingSource> recording;
  std::unique_ptr<DriverReplay> replay;
  std::unique_ptr<LiveCamera> camera_driver;  // OpenNI2 or V4L2 (+ the GPIO trigger)
  std::unique_ptr<drivers::SerialImuDriver> imu_driver;
  if (!o.recording.empty() && !o.through_drivers) {
    recording = std::make_unique<RecordingSource>(
        RecordingSourceSettings{.path = o.recording,
                                .lockstep = o.lockstep,
                                .wait_timeout_ns = o.wait_timeout_ns,
                                .depth_scale_m = depth_scale_m,
                                .max_frames = o.max_frames,
                                .thread = table_spec("rgbd_driver", rtc)},
        pool, frames, imu);
  } else {
    if (o.lockstep)
      throw std::runtime_error("--lockstep needs a recording played without the drivers");
    drivers::SerialImuDriverSettings ims = drivers::serial_imu_settings(cfg.imu, rtc);
    if (o.through_drivers) {
      replay = std::make_unique<DriverReplay>(
          DriverReplaySettings{.recording = o.recording,
                               .max_frames = o.max_frames,
                               .faults = o.driver_faults,
                               .feeder_thread = table_spec("sensor_replay", rtc)});
      drivers::Openni2DriverSettings cam = drivers::openni2_settings(cfg.camera, rtc);
      cam.uri = replay->clip_path();
      cam.width_px = static_cast<std::uint32_t>(camera.width_px);
      cam.height_px = static_cast<std::uint32_t>(camera.height_px);
      cam.playback_speed = 1.0;  // the driver paces the clip in real time
      // Opened on the driver's own thread, so OpenNI2's player thread inherits its real-time
      // priority and CPU: the "sensor" is not starved by the SCHED_FIFO tracker pair (opened
      // from this SCHED_OTHER thread it fell ~19 ms behind per second of stream).
      cam.wait_for_device = true;
      // The camera fault: a stalled clip is a lost camera, reopened when it is back.
      cam.reopen_files = o.driver_faults.camera_gone();
      if (cam.reopen_files) cam.frame_timeout_ms = 400;
      ims.port = replay->imu_port();
      ims.protocol = "xsens_mt";
      ims.stamper.nominal_rate_hz = replay->imu_rate_hz();
      camera_driver = LiveCamera::openni2(cam, pool, frames);
    } else {
      if (cfg.imu.driver != "serial")
        throw std::runtime_error("live sensors need imu.driver serial");
      camera_driver = LiveCamera::robot(cfg, pool, frames, o.camera_seams);  // openni2 or v4l2
    }
    imu_driver = std::make_unique<drivers::SerialImuDriver>(ims, imu);
    if (recorder) {  // each driver also feeds the recorder's tap (full: drop newest, count)
      camera_driver->set_tap(&taps->frames);
      imu_driver->set_taps(&taps->imu, &taps->bytes);
      recorder->add_frames(pool, taps->frames,
                           {camera.fx_px, camera.fy_px, camera.cx_px, camera.cy_px});
      recorder->add_imu(taps->imu);
      recorder->add_serial(taps->bytes, ims.port);
      recorder->add_poses(taps->poses, cfg.dds.map_frame_id);
      if (camera_driver->triggered()) {  // the frame-sync edges, as `vigs record` writes them
        camera_driver->set_edge_tap(&taps->edges);
        recorder->add_edges(taps->edges, camera_driver->trigger_source());
      }
    }
  }
  if (o.mapping) handoff.emplace(kKeyframeSlots, camera.width_px * camera.height_px);

  // 4. Stages: tracker, mapper, publisher.
  LiveTrackerSettings ts;
  ts.lockstep = o.lockstep;
  ts.wait_timeout_ns = o.wait_timeout_ns;
  ts.depth_scale_m = depth_scale_m;
  ts.camera = camera;
  // The tracker's team member 1 on the other CPU at the tracker's priority: without it the
  // worker was made by the tracker thread at normal priority and inherited its CPU, so the
  // "parallel" preprocessing and GICP took turns on one CPU (track 24.6 / 44.1 ms p50 / p99
  // through the drivers against 12.7 / 25.1 in `vigs replay`; BENCHMARKS.md, Live pipeline).
  ts.odometry.worker = table_spec("tracker_w1", rtc);
  rt::ThreadSpec tracker_spec = table_spec("tracker", rtc);
  tracker_spec.period_ns = o.lockstep ? rt::ms_to_ns(1) : period_ns(cfg.camera.rate_hz);
  if (!o.lockstep && cfg.rt.tracker_phase_lock) {
    ts.phase_lock.period_ns = tracker_spec.period_ns;
    ts.phase_lock.lead_ns = std::llround(cfg.rt.tracker_phase_lead_ms * 1e6);
  }
  // The drivers' corrupt IMU bytes and camera losses flag the next pose.
  const DriverFaultTotals driver_faults(camera_driver.get(), imu_driver.get());
  if (camera_driver || imu_driver) ts.driver_faults = &driver_faults;
  LiveTracker tracker(cfg, ts, {pool, frames, imu, poses, results, handoff ? &*handoff : nullptr});
  // The tick slides toward the frames' arrival (LiveTracker's phase lock) at the same rate.
  rt::PeriodicTask tracker_task(
      tracker_spec, [&tracker, &tracker_task](const rt::PeriodicTask::Cycle& c) {
        if (const std::int64_t shift = tracker.tick(c.wake_ns); shift != 0)
          tracker_task.shift_next_deadline(shift);
      });

  std::unique_ptr<LiveMapper> mapper;
  std::unique_ptr<rt::PeriodicTask> mapper_task;
  if (o.mapping) {
    mapper = std::make_unique<LiveMapper>(
        cfg.mapping, camera, depth_scale_m, pool, *handoff, table_spec("mapper_w1", rtc),
        cfg.tracking.preprocess.depth.pixel_stride, &cfg.tracking);
    rt::ThreadSpec mapper_spec = table_spec("mapper", rtc);
    mapper_spec.period_ns = period_ns(cfg.mapping.rate_hz);
    mapper_task = std::make_unique<rt::PeriodicTask>(mapper_spec, [&m = *mapper] { m.tick(); });
    // Best effort: a tick that ran past its period (one with keyframes always does) is followed
    // at once; the period only paces a mapper that has nothing to train yet.
    mapper_task->set_overrun(rt::PeriodicTask::Overrun::kRunAtOnce);
  }

  dds::DdsConfig dds_config = dds::resolve_dds_config(cfg.dds, o.config_path);
  if (o.dds_domain) dds_config.domain_id = *o.dds_domain;
  dds::PosePublisher::StatusMailbox status(1);
  dds::PosePublisher publisher(dds_config, poses, &status, cfg.robot);

  if (o.wait_for_subscribers > 0) {  // readers of <prefix>/pose (odom and tf need not match)
    const std::int64_t give_up = rt::monotonic_ns() + rt::s_to_ns(std::int64_t{30});
    while (publisher.pose_subscribers() < o.wait_for_subscribers) {
      if (rt::monotonic_ns() > give_up)
        throw std::runtime_error("fewer than " + std::to_string(o.wait_for_subscribers) +
                                 " pose subscribers on DDS domain " +
                                 std::to_string(dds_config.domain_id) + " within 30 s");
      rt::sleep_until_ns(rt::monotonic_ns() + rt::ms_to_ns(10));
    }
  }

  // The progress line's ETA: a recording's end is known (its frames, or --frames); live has none.
  std::uint64_t frames_total = 0;
  if (progress && !o.recording.empty()) {
    frames_total = RecordingSource::frame_count(o.recording);
    if (o.max_frames > 0)
      frames_total = std::min(frames_total, static_cast<std::uint64_t>(o.max_frames));
  }

  // 5. Start: consumers first, sources last.
  publisher.start(table_spec("dds_pub", rtc));
  if (mapper_task) mapper_task->start();
  tracker_task.start();
  if (recorder) recorder->start();  // the file exists before any driver runs
  if (recording) recording->start();
  if (imu_driver) imu_driver->start();
  if (camera_driver) camera_driver->start();                    // its trigger (gpio_trigger) first
  if (replay) replay->start(*camera_driver->openni2_driver());  // the IMU: the clip's clock

  // 6. Run: collect results, status at 1 Hz, progress at 2 Hz, until the end or a stop.
  const std::int64_t t_start = rt::monotonic_ns();
  std::int64_t next_status = t_start, next_progress = t_start;
  std::vector<float> track_ms;
  std::vector<std::int64_t> latency_ns, wait_ns;  // arrival -> pose pushed; arrival -> tick
  std::vector<std::int64_t> done_ns;              // per pose: when it was pushed
  bool ended = false;
  PoseQualityCounts pose_quality;
  LiveStatusSources status_sources{
      &tracker_task, mapper_task.get(),   &tracker,         mapper.get(), &frames, &imu,
      &poses,        camera_driver.get(), imu_driver.get(), &pose_quality};
  const auto source_counters = [&] {
    if (recording) return recording->counters();
    RecordingSourceCounters c;
    if (camera_driver) {
      const drivers::RgbdDriverCounters d = camera_driver->counters();
      c.frames = d.delivered;
      c.frame_drops = d.dropped_ring_full + d.dropped_pool_empty;
    }
    if (imu_driver) {
      const drivers::SerialImuFaults f = imu_driver->faults();
      c.imu_samples = f.samples_out;
      c.imu_drops = f.ring_drops;
    }
    return c;
  };
  const auto record_counters = [&] {
    LiveRecordResult c;
    c.file = o.record_path;
    c.written = recorder->stats();
    c.frame_tap_drops = camera_driver->counters().tap_dropped;
    const drivers::SerialImuFaults f = imu_driver->faults();
    c.imu_tap_drops = f.tap_sample_drops;
    c.serial_tap_drops = f.tap_byte_drops;
    c.pose_tap_drops = taps->pose_drops;
    if (const auto t = camera_driver->trigger_counters()) c.edge_tap_drops = t->tap_dropped;
    return c;
  };
  const auto drain = [&] {
    LiveFrameResult r;
    while (results.try_pop(r)) {
      if (r.end_of_stream) {
        ended = true;
        continue;
      }
      const std::uint64_t index = out.replay.frames.size();
      if (taps && !taps->poses.try_push(recorded_pose(r, index))) ++taps->pose_drops;
      pose_quality.add(pose_source(r.frame, index), r.flags);  // the pose's flags, frame's included
      out.replay.frames.push_back(r.frame);
      out.pose_flags.push_back(r.flags);
      track_ms.push_back(static_cast<float>(rt::ns_to_ms(r.track_ns)));
      done_ns.push_back(r.done_mono_ns);
      if (r.arrival_ns > 0) {
        latency_ns.push_back(r.done_mono_ns - r.arrival_ns);
        if (r.wake_ns > 0) wait_ns.push_back(r.wake_ns - r.arrival_ns);
      }
    }
  };
  while (!ended) {
    if (o.stop != nullptr && o.stop->load(std::memory_order_relaxed) != 0) {
      out.stopped_by_signal = true;
      break;
    }
    if (tracker.failed() || (replay && replay->failed())) break;
    drain();
    const std::int64_t now = rt::monotonic_ns();
    if (now >= next_status) {
      status.push(make_status_snapshot(status_sources, now));
      next_status = now + dds::PosePublisher::kStatusPeriodNs;
    }
    if (progress && now >= next_progress) {
      LiveProgress p;
      p.frames = out.replay.frames.size();
      p.frames_total = frames_total;
      p.elapsed_s = rt::ns_to_s(now - t_start);
      if (!out.replay.frames.empty())
        p.stream_s = rt::ns_to_s(out.replay.frames.back().t_ns - out.replay.frames.front().t_ns);
      p.track_p50_ns = tracker_task.cycle_time().p50();
      p.track_p99_ns = tracker_task.cycle_time().p99();
      const RecordingSourceCounters sc = source_counters();
      p.frames_played = sc.frames + sc.frame_drops;
      p.drops = total_drops(status_sources) + sc.frame_drops + sc.imu_drops;
      if (mapper) p.gaussians = mapper->gaussians();
      if (recorder) {
        const LiveRecordResult rc = record_counters();
        p.recording = true;
        p.record_mb = static_cast<double>(rc.written.bytes_written) * 1e-6;
        p.record_drops = rc.tap_drops();
      }
      progress(p);
      next_progress = now + rt::ms_to_ns(500);
    }
    rt::sleep_until_ns(now + rt::ms_to_ns(5));
  }

  // 7. Drain and join: sources first (the feeder before the IMU driver that reads its pty),
  // then the tracker (its last results), mapper, publisher.
  // At the clip's end the feeder still owes the IMU samples past the last frame, and the IMU
  // driver the bytes still in the pty: both are let finish (bounded) before they stop.
  if (replay) replay->finish(ended ? rt::ms_to_ns(250) : 0);
  if (camera_driver) camera_driver->stop();  // then its trigger
  if (imu_driver && replay && ended) {
    const std::uint64_t sent = replay->counters().imu_samples_written;
    (void)rt::poll_until(
        [&] {
          const drivers::SerialImuFaults f = imu_driver->faults();
          return f.samples_out + f.bad_checksum >= sent;
        },
        rt::ms_to_ns(100));
  }
  if (imu_driver) imu_driver->stop();
  if (recording) recording->stop();
  tracker_task.stop();
  drain();
  if (mapper_task) {
    // Give the mapper the keyframes already queued (it stops at the end marker or now).
    (void)rt::poll_until(
        [&] { return out.stopped_by_signal || mapper->ended() || tracker.failed(); },
        rt::s_to_ns(std::int64_t{10}), rt::ms_to_ns(5));
    mapper_task->stop();
  }
  publisher.stop();  // one last drain
  if (recorder) {    // every tap drained, the summary written; then the name is the final one
    recorder->stop();
    out.record = record_counters();
    std::filesystem::rename(record_partial, o.record_path);
  }
  if (publisher.enabled()) (void)publisher.wait_for_acknowledgments(std::chrono::seconds(2));
  if (tracker.failed()) throw std::runtime_error(tracker.failure_message());
  if (recording && !recording->error().empty()) throw std::runtime_error(recording->error());
  if (replay && !replay->error().empty()) throw std::runtime_error(replay->error());
  {
    rt::FrameHandle h;
    while (frames.try_pop(h)) pool.release(h);
  }

  // 8. Results.
  const std::int64_t wall_ns = rt::monotonic_ns() - t_start;
  ReplayResult& r = out.replay;
  r.counters = tracker.odometry_counters();
  if (const rt::RtThread* w = tracker.team_worker()) {
    out.tracker_worker = w->spec();
    out.tracker_worker_status = w->status();
  }
  if (const rt::PeriodicTask* p = publisher.task()) out.publisher_thread = p->spec();
  r.camera = camera;
  r.guess = cfg.tracking.initial_guess;
  (void)parse_fusion_mode(cfg.tracking.fusion, r.fusion);  // checked by the config loader
  r.initial_pose = tracker.initial_pose();
  r.wall_s = rt::ns_to_s(wall_ns);
  r.track_ms = track_ms;
  for (float ms : track_ms) r.track_s += ms * 1e-3;
  out.tracker = tracker.counters();
  r.imu_samples_fed = out.tracker.imu_samples;
  out.source = source_counters();
  if (recording) r.imu_samples = out.source.imu_samples;
  if (camera_driver) {
    out.camera_driver = camera_driver->counters();
    out.trigger = camera_driver->trigger_counters();
    out.trigger_match = camera_driver->trigger_match_counters();
  }
  if (imu_driver) out.imu_driver = imu_driver->faults();
  // The poses published live stay as tracked; corrected in the tracker's clock, as its keyframes.
  if (tracking::LoopCloser* lc = mapper ? mapper->loop_closer() : nullptr) {
    apply_loop_closure(*lc, r);
    mapper->follow_loop_closures();  // the mapper task has stopped; the map follows the graph
  }
  if (replay) {
    // Back to the recording's clock (driver_replay.hpp): the RESULTS_DIR is evaluated in it.
    out.feeder = replay->counters();
    out.host_minus_recording_ns = replay->host_minus_recording_ns().value_or(0);
    for (TrackedFrame& f : r.frames) f.t_ns -= out.host_minus_recording_ns;
    r.imu_samples = out.source.imu_samples;
  }
  if (mapper) {
    r.map = std::make_shared<const mapping::GaussianMap>(mapper->mapper().map());
    r.map_iterations = static_cast<long>(mapper->mapper().iterations());
    r.map_coarse_iterations = static_cast<long>(mapper->mapper().coarse_iterations());
    r.map_s = rt::ns_to_s(mapper->busy_ns());
    r.map_seen_through_pruned = mapper->mapper().seen_through_pruned();
    r.map_refined_closer = mapper->mapper().refined_closer();
    r.map_nonfinite_gradients = mapper->mapper().nonfinite_gradients();
    r.map_moved_by_loops = mapper->mapper().moved_by_corrections();
    r.map_budget_ms = cfg.mapping.budget_ms;
    r.map_budget_overruns = mapper->mapper().budget_overruns();
    r.map_memory = mapper->mapper().memory();
    r.map_bytes_per_gaussian = r.map_memory.bytes_per_gaussian();
    r.map_gated_points = mapper->mapper().gated_points();
  }
  const dds::PosePublisher::Stats ps = publisher.stats();
  out.poses_published = ps.poses_published;
  out.status_published = ps.status_published;
  out.tracker_cycles = tracker_task.cycles();
  out.tracker_overruns = tracker_task.overruns();
  out.tracker_missed = tracker_task.missed_deadlines();
  out.cycle_p50_ns = tracker_task.cycle_time().p50();
  out.cycle_p99_ns = tracker_task.cycle_time().p99();
  if (const std::optional<double> p50 = track_ms_quantile(r, 0.5)) {
    out.track_p50_ns = std::llround(1e6 * *p50);
    out.track_p99_ns = std::llround(1e6 * *track_ms_quantile(r, 0.99));
  }
  out.drops = total_drops(status_sources) + out.source.frame_drops + out.source.imu_drops;
  if (out.trigger) out.drops += out.trigger->dropped_ring_full;  // edges the driver never saw
  out.pose_latency_ns = quantiles(latency_ns);
  out.frame_wait_ns = quantiles(wait_ns);
  out.tracker_phase_shift_ns = tracker_task.phase_shift_ns();
  if (r.frames.size() >= 2) {
    out.stream_s = rt::ns_to_s(r.frames.back().t_ns - r.frames.front().t_ns);
    out.real_time_factor = r.wall_s > 0 ? out.stream_s / r.wall_s : 0;
    std::vector<std::int64_t> stream_ns(r.frames.size());
    for (std::size_t i = 0; i < r.frames.size(); ++i) stream_ns[i] = r.frames[i].t_ns;
    out.real_time_factor_steady = steady_real_time_factor(stream_ns, done_ns);
    // Overruns in the same window (the task is joined: its overrun times are complete). More
    // overruns than it logs: all of them count, an upper bound.
    const std::span<const std::int64_t> overran = tracker_task.overrun_end_times_ns();
    out.tracker_overruns_steady = out.tracker_overruns > overran.size()
                                      ? std::optional<std::uint64_t>(out.tracker_overruns)
                                      : events_in_steady_window(done_ns, overran);
  }
  return out;
}

}  // namespace vigs::pipeline
