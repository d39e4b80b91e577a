#include "pipeline/lockstep_replay.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <span>

#include "core/geometry/body_from_camera.hpp"
#include "inertial/gravity_alignment.hpp"
#include "io/io_error.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/recording/recorded_frames.hpp"
#include "io/ros_msgs/time_reference.hpp"
#include "io/ros_msgs/typed_io.hpp"
#include "pipeline/lockstep_mapping.hpp"
#include "pipeline/map_loop_correction.hpp"

namespace vigs::pipeline {
namespace {

/// Thrown from the frame callback to stop reading after max_frames.
struct StopReading {};

/// A frame `vigs run --record` tracked, and the newest IMU sample it used (/vigs/pose/imu_used).
struct RunFrame {
  std::int64_t t_ns = 0, imu_t_ns = 0;
};

std::vector<RunFrame> read_run_frames(const std::string& path) {
  std::vector<RunFrame> run;
  io::mcap::McapReader reader(path);
  io::mcap::MessageView m;
  while (reader.next(m)) {
    io::ros_msgs::TimeReference ref;
    if (m.channel->topic != io::topics::kTrackerImu.name || !io::ros_msgs::decode_message(m, ref))
      continue;
    run.push_back({ref.header.stamp.to_ns(), ref.time_ref.to_ns()});
  }
  if (run.empty())
    throw RecordingError(path + ": no messages on " + std::string(io::topics::kTrackerImu.name) +
                         " to replay as the run did (written by vigs run --record)");
  std::sort(run.begin(), run.end(),
            [](const RunFrame& a, const RunFrame& b) { return a.t_ns < b.t_ns; });
  return run;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

std::size_t ImuFeeder::feed_until(std::int64_t t_frame_ns, Odometry& odometry) {
  std::size_t n = 0;
  while (next_ < imu_.size() && imu_[next_].t_ns <= t_frame_ns) {
    odometry.add_imu(imu_[next_++]);
    ++n;
  }
  return n;
}

const char* to_string(InitialPoseSource source) {
  switch (source) {
    case InitialPoseSource::ground_truth:
      return "ground_truth";
    case InitialPoseSource::gravity:
      return "gravity";
    case InitialPoseSource::identity:
      return "identity";
  }
  return "unknown";
}

const char* to_string(MapPoseSource source) {
  return source == MapPoseSource::ground_truth ? "ground_truth" : "estimate";
}

geometry::Pose initial_camera_pose(const RecordedMotion& motion, std::int64_t t_first_ns,
                                   const config::RobotConfig& cfg, InitialPoseSource& used,
                                   InitialPoseSource prefer) {
  const geometry::Pose T_b_c = geometry::body_from_camera(cfg.extrinsics);
  const auto T_w_b_gt = prefer == InitialPoseSource::ground_truth || motion.imu.empty()
                            ? interpolate_pose(motion.body_poses, t_first_ns)
                            : std::nullopt;
  if (T_w_b_gt) {
    used = InitialPoseSource::ground_truth;
    return *T_w_b_gt * T_b_c;
  }
  std::size_t begin = 0, end = 0;
  for (std::size_t i = 0; i < motion.imu.size(); ++i) {
    const std::int64_t t = motion.imu[i].t_ns;
    if (t < t_first_ns - kRestWindowNs) begin = i + 1;
    if (t <= t_first_ns) end = i + 1;
  }
  if (begin == motion.imu.size()) {  // the IMU stopped before the window: its last samples
    begin -= std::min(begin, kMinRestSamples);
  }
  end = std::max(end, std::min(motion.imu.size(), begin + kMinRestSamples));
  const std::span<const ImuSample> at_rest(motion.imu.data() + begin, end - begin);
  if (const auto R_w_b = inertial::gravity_aligned_R_w_b(at_rest, t_first_ns)) {
    used = InitialPoseSource::gravity;
    geometry::Pose T_w_b = geometry::Pose::Identity();
    T_w_b.linear() = *R_w_b;
    return T_w_b * T_b_c;
  }
  used = InitialPoseSource::identity;
  return geometry::Pose::Identity();
}

void apply_loop_closure(tracking::LoopCloser& loops, ReplayResult& r) {
  loops.optimize();
  r.loop = loops.stats();
  r.frames_odometry.clear();
  r.frames_odometry.reserve(r.frames.size());
  for (TrackedFrame& f : r.frames) {
    r.frames_odometry.push_back(f.T_w_c);
    f.T_w_c = loops.corrected(f.t_ns, f.T_w_c);
  }
}

ReplayResult replay_recording(const std::string& path, const config::RobotConfig& cfg,
                              const ReplayOptions& options,
                              const std::function<void(const TrackedFrame&)>& on_frame) {
  const auto t0 = std::chrono::steady_clock::now();
  ReplayResult result;
  const RecordedMotion motion =
      read_recorded_motion(path, options.imu_topic, options.pose_topic, options.allow_damaged);
  result.damage = motion.damage;
  result.imu_samples = motion.imu.size();

  std::optional<Odometry> odometry;
  std::optional<LockstepMapper> mapper;
  std::optional<tracking::LoopCloser> loops;
  if (cfg.tracking.loop.enabled) loops.emplace(cfg.tracking.loop, cfg.tracking.gicp);
  MapLoopCorrection map_correction;  // the map follows the loop closer (map_loop_correction.hpp)
  const bool map_at_truth = options.map_poses == MapPoseSource::ground_truth &&
                            (options.map_budget_ms > 0.0 || options.map_iterations_per_frame > 0);
  if (map_at_truth && motion.body_poses.empty())
    throw RecordingError(path + ": no geometry_msgs/PoseStamped on " + options.pose_topic +
                         " to build the map at the ground-truth poses");
  const geometry::Pose T_b_c = geometry::body_from_camera(cfg.extrinsics);
  // The map follows the loop closer only when it was built at the estimate.
  const bool map_follows_loops = cfg.mapping.follow_loop_closures && !map_at_truth;
  ImuFeeder feeder(motion.imu);
  std::int64_t last_t_ns = 0;
  // as_run: the frames the recording's run tracked and the newest IMU sample each one used.
  const std::vector<RunFrame> run =
      options.as_run ? read_run_frames(path) : std::vector<RunFrame>{};
  const auto on_recorded = [&](const io::RecordedFrame& rec) {
    const std::int64_t t_ns = rec.view.t_ns;
    std::int64_t imu_until_ns = t_ns;  // the samples up to here go in before the frame
    if (options.as_run) {
      const auto it =
          std::lower_bound(run.begin(), run.end(), t_ns,
                           [](const RunFrame& f, std::int64_t t) { return f.t_ns < t; });
      if (it == run.end() || it->t_ns != t_ns) {
        ++result.frames_not_tracked_by_run;
        return;
      }
      imu_until_ns = std::min(t_ns, it->imu_t_ns);
    }
    if (result.frames_skipped_at_start < options.skip_frames) {
      ++result.frames_skipped_at_start;
      return;
    }
    if (!odometry) {
      OdometryOptions opt;
      opt.guess = options.guess;
      opt.fusion = options.fusion;
      // as_run: the run started with the samples it had then.
      RecordedMotion had;
      const bool cut = imu_until_ns < t_ns;
      if (cut) {
        had = motion;
        std::erase_if(had.imu, [&](const ImuSample& s) { return s.t_ns > imu_until_ns; });
      }
      opt.initial_T_w_c = initial_camera_pose(cut ? had : motion, t_ns, cfg, result.initial_pose,
                                              options.initial_pose);
      odometry.emplace(cfg, rec.camera, opt);
      // Without samples the frontend would integrate zero specific force: free fall.
      if (odometry->guess_mode() == tracking::InitialGuessMode::imu && motion.imu.empty()) {
        throw RecordingError(path + ": no sensor_msgs/Imu messages on " + options.imu_topic +
                             " for the imu guess (use previous_pose or constant_velocity)");
      }
      if (options.map_budget_ms > 0.0 || options.map_iterations_per_frame > 0) {
        mapper.emplace(cfg.mapping, rec.camera, options.map_iterations_per_frame,
                       options.map_budget_ms, cfg.tracking.preprocess.depth.pixel_stride);
        mapper->keep_frames(cfg.tracking.moving_window_frames + 1);
      }
      result.camera = rec.camera;
      result.guess = odometry->guess_mode();
      result.fusion = odometry->fusion_mode();
      result.frames.reserve(options.max_frames > 0 ? static_cast<std::size_t>(options.max_frames)
                                                   : 1024);
    } else {
      if (rec.camera.width_px != result.camera.width_px ||
          rec.camera.height_px != result.camera.height_px ||
          rec.camera.fx_px != result.camera.fx_px || rec.camera.fy_px != result.camera.fy_px ||
          rec.camera.cx_px != result.camera.cx_px || rec.camera.cy_px != result.camera.cy_px) {
        throw RecordingError(path + ": frame " + std::to_string(rec.index) +
                             ": camera intrinsics change during the recording");
      }
      if (t_ns <= last_t_ns) {
        throw RecordingError(path + ": frame " + std::to_string(rec.index) +
                             ": stamp not after the previous frame's");
      }
    }
    last_t_ns = t_ns;
    feeder.feed_until(imu_until_ns, *odometry);
    // A frame without depth is tracked with no measurement anywhere (and so is lost).
    if (!rec.view.has_depth()) ++result.frames_without_depth;
    if (mapper) mapper->keep_frame(rec.view);
    const auto t_track = std::chrono::steady_clock::now();
    const TrackedFrame f = odometry->track(rec.view);
    const double track_s = seconds_since(t_track);
    result.track_s += track_s;
    result.track_ms.push_back(static_cast<float>(1e3 * track_s));
    bool closed = false;
    std::optional<geometry::Pose> T_w_c_map;  // with loops: the keyframe's solved pose
    if (loops && f.keyframe) {
      closed = loops->add_keyframe(odometry->tracker().last_keyframe(), f.reinitialized);
      if (mapper && map_follows_loops) T_w_c_map = map_correction.place(*loops);
    }
    if (mapper && map_at_truth && f.keyframe) {
      const std::int64_t t_kf_ns = odometry->tracker().last_keyframe().t_ns;
      const auto T_w_b = interpolate_pose(motion.body_poses, t_kf_ns);
      if (!T_w_b)
        throw RecordingError(path + ": no ground-truth pose on " + options.pose_topic + " within " +
                             std::to_string(kMaxPoseGapNs / 1'000'000) +
                             " ms of the keyframe at t_ns " + std::to_string(t_kf_ns) +
                             " (map poses: ground_truth)");
      T_w_c_map = *T_w_b * T_b_c;
    }
    if (mapper) {
      const auto t_map = std::chrono::steady_clock::now();
      // A keyframe may come moving_window_frames late (the moving test): train it on its own
      // frame, kept since.
      if (f.keyframe && !mapper->add_keyframe(odometry->tracker().last_keyframe(),
                                              T_w_c_map ? &*T_w_c_map : nullptr)) {
        ++result.keyframes_without_view;
      }
      mapper->step();  // inserts the keyframe first: a closure below moves it too
      if (closed && map_follows_loops) map_correction.apply(*loops, mapper->mapper());
      result.map_s += seconds_since(t_map);
    }
    result.frames.push_back(f);
    if (on_frame) on_frame(f);
    if (options.max_frames > 0 &&
        static_cast<std::int64_t>(result.frames.size()) >= options.max_frames) {
      throw StopReading{};
    }
  };
  try {
    const io::McapFrameStats st = io::for_each_recorded_frame(path, on_recorded);
    if (st.damage.damaged()) {
      if (!options.allow_damaged) {
        throw RecordingError("damaged recording (" + st.damage.kind + "): " + st.damage.message +
                             " (vigs replay --allow-truncated replays the intact part)");
      }
      if (!result.damage.damaged()) result.damage = st.damage;
    }
  } catch (const StopReading&) {
  } catch (const RecordingError&) {
    throw;
  } catch (const io::IoError& e) {
    throw RecordingError(e.what());
  } catch (const std::runtime_error& e) {  // for_each_recorded_frame names the file and offset
    throw RecordingError(e.what());
  }
  if (!odometry && result.frames_skipped_at_start > 0)
    throw RecordingError(path + ": all " + std::to_string(result.frames_skipped_at_start) +
                         " frames skipped at the start (skip_frames " +
                         std::to_string(options.skip_frames) + ")");
  if (!odometry)
    throw RecordingError(path + ": no RGB-D frames on " + std::string(io::topics::kRgb.name));
  result.counters = odometry->counters();
  if (loops) {
    apply_loop_closure(*loops, result);
    if (mapper && map_follows_loops)
      map_correction.apply(*loops, mapper->mapper());  // the graph's last solution
  }
  result.imu_samples_fed = feeder.fed();
  if (mapper) {
    result.map = std::make_shared<const mapping::GaussianMap>(mapper->map());
    result.map_iterations = static_cast<long>(mapper->mapper().iterations());
    result.map_coarse_iterations = static_cast<long>(mapper->mapper().coarse_iterations());
    result.map_budget_ms = options.map_budget_ms;
    result.map_poses = options.map_poses;
    result.map_budget_overruns = mapper->mapper().budget_overruns();
    result.map_memory = mapper->mapper().memory();
    result.map_bytes_per_gaussian = result.map_memory.bytes_per_gaussian();
    result.map_gated_points = mapper->mapper().gated_points();
    result.map_seen_through_pruned = mapper->mapper().seen_through_pruned();
    result.map_refined_closer = mapper->mapper().refined_closer();
    result.map_nonfinite_gradients = mapper->mapper().nonfinite_gradients();
    result.map_moved_by_loops = mapper->mapper().moved_by_corrections();
  }
  result.wall_s = seconds_since(t0);
  return result;
}

}  // namespace vigs::pipeline
