// The odometry on a simulated office sequence: lockstep replay is deterministic, the IMU guess
// tracks with a small ATE where GS-ICP SLAM's previous-pose guess slides along the corridor,
// and lost frames are bridged by IMU propagation until tracking resumes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "inertial/inertial_frontend.hpp"
#include "io/recording/recorded_frames.hpp"
#include "pipeline/lockstep_replay.hpp"
#include "pipeline/odometry.hpp"
#include "pipeline/replay_figures.hpp"
#include "tests/pipeline/sim_sequence.hpp"

namespace vigs::pipeline {
namespace {

using testing::TempDir;

constexpr double kSeconds = 5.0;  // 2 s at rest, then about 3 m of corridor

/// Each test process simulates its own copy (ctest runs the tests in parallel processes).
class SimulatedOffice : public ::testing::Test {
 protected:
  void SetUp() override {
    cfg_ = testing::small_office(kSeconds);
    path_ = dir_.file("office.mcap");
    testing::simulate(cfg_, path_);
    motion_ = read_recorded_motion(path_);
  }
  ReplayResult replay(tracking::InitialGuessMode mode) {
    ReplayOptions opt;
    opt.guess = mode;
    return replay_recording(path_, cfg_, opt);
  }

  TempDir dir_;
  config::RobotConfig cfg_;
  std::string path_;
  RecordedMotion motion_;
};

bool bit_identical(const geometry::Pose& a, const geometry::Pose& b) {
  return std::memcmp(a.matrix().data(), b.matrix().data(), sizeof(double) * 16) == 0;
}

TEST_F(SimulatedOffice, LockstepReplayIsBitIdenticalRunToRun) {
  const ReplayResult a = replay(tracking::InitialGuessMode::imu);
  const ReplayResult b = replay(tracking::InitialGuessMode::imu);
  ASSERT_EQ(a.frames.size(), 101u);
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (std::size_t i = 0; i < a.frames.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(a.frames[i].t_ns, b.frames[i].t_ns);
    EXPECT_TRUE(bit_identical(a.frames[i].T_w_c, b.frames[i].T_w_c));
    EXPECT_EQ(a.frames[i].status, b.frames[i].status);
    EXPECT_EQ(a.frames[i].keyframe, b.frames[i].keyframe);
  }
  // Every IMU sample up to the last frame was fed, none after it.
  EXPECT_EQ(a.imu_samples_fed, motion_.imu.size());
  EXPECT_EQ(a.initial_pose, InitialPoseSource::gravity);  // the default: no ground truth
}

TEST_F(SimulatedOffice, ImuGuessTracksEveryFrameWithCentimetreAte) {
  const ReplayResult r = replay(tracking::InitialGuessMode::imu);
  EXPECT_EQ(r.counters.lost, 0);
  EXPECT_EQ(r.counters.tracked + r.counters.not_converged, static_cast<long>(r.frames.size()) - 1);
  EXPECT_EQ(r.counters.imu_guesses, static_cast<long>(r.frames.size()) - 1);
  EXPECT_EQ(r.counters.imu_resets, static_cast<long>(r.frames.size()));
  // The 2 s at rest (40 frame intervals, the first 0.2 s too short for the stillness window)
  // are zero-velocity updates. The walk's even stretches read as rest to the accelerometer
  // too; the tracked speed refuses them.
  std::printf("zero-velocity updates %ld, gated %ld\n", r.counters.zero_velocity_updates,
              r.counters.zupt_gated);
  EXPECT_GE(r.counters.zero_velocity_updates, 30);
  EXPECT_LE(r.counters.zero_velocity_updates, 40);
  EXPECT_GT(r.counters.zupt_gated, 0);
  const eval::AteResult ate = testing::camera_ate(motion_, r.frames, cfg_);
  EXPECT_EQ(ate.pairs, r.frames.size());
  std::printf("imu guess: ATE rmse %.4f m, max %.4f m over %zu frames\n", ate.stats.rmse,
              ate.stats.max, ate.pairs);
  // Bound: 3 cm RMSE over ~3 m of walking.
  EXPECT_LT(ate.stats.rmse, 0.03);
  EXPECT_LT(ate.stats.max, 0.08);
  // The IMU guess starts GICP close: a few linearisations a frame, not a damping ladder of
  // refused steps (gicp_impl.hpp).
  const double iterations = mean_gicp_iterations(r).value_or(0.0);
  std::printf("GICP iterations per frame: %.2f\n", iterations);
  EXPECT_LT(iterations, 5.0);
}

TEST_F(SimulatedOffice, NotConvergedPosesAreCountedApartFromTracked) {
  // One GICP iteration per frame: on the walk, GICP stops at max_iterations before its step
  // falls below the threshold. Those poses are used but counted as not_converged, not as
  // tracked: every frame after the first is exactly one of tracked, not_converged or lost.
  cfg_.tracking.gicp.max_iterations = 1;
  const ReplayResult r = replay(tracking::InitialGuessMode::imu);
  const OdometryCounters& c = r.counters;
  std::printf("1 GICP iteration: tracked %ld, not converged %ld, lost %ld of %zu frames\n",
              c.tracked, c.not_converged, c.lost, r.frames.size());
  EXPECT_GT(c.not_converged, 0);
  EXPECT_EQ(c.tracked + c.not_converged + c.lost, static_cast<long>(r.frames.size()) - 1);
}

TEST_F(SimulatedOffice, PreviousPoseBaselineDriftsWhereTheImuGuessDoesNot) {
  const ReplayResult prev = replay(tracking::InitialGuessMode::previous_pose);
  EXPECT_EQ(prev.counters.imu_guesses, 0);
  const double ate_prev = testing::camera_ate(motion_, prev.frames, cfg_).stats.rmse;
  std::printf("previous_pose: ATE rmse %.4f m\n", ate_prev);
  // GICP from the previous pose converges short along the corridor, frame after frame: more
  // than 5x the bound the imu guess meets above (same sequence, same settings).
  EXPECT_GT(ate_prev, 5.0 * 0.03);
}

TEST_F(SimulatedOffice, GicpHalvesTheImuOnlyError) {
  // GICP must do the work: with every GICP result rejected (max_correction_m 0) the odometry
  // is IMU dead reckoning from the same start (and the map never restarts, which would restart
  // the IMU state too). A no-op GICP would leave the two equal. The simulated IMU's biases
  // start at zero, and from a level start 5 s of dead reckoning are then within a centimetre;
  // a real MEMS IMU starts with a turn-on bias, given here (0.3 deg/s, 4 mg).
  std::vector<ImuSample> imu = motion_.imu;
  for (ImuSample& s : imu) {
    s.gyro_rps[0] += 0.003;
    s.gyro_rps[1] -= 0.004;
    s.gyro_rps[2] += 0.0035;
    s.accel_mps2[0] += 0.03;
    s.accel_mps2[1] -= 0.02;
    s.accel_mps2[2] += 0.03;
  }
  const auto track = [&](const config::RobotConfig& cfg) {
    std::optional<Odometry> odometry;
    RecordedMotion biased = motion_;
    biased.imu = imu;
    ImuFeeder feeder(imu);
    std::vector<TrackedFrame> frames;
    io::for_each_recorded_frame(path_, [&](const io::RecordedFrame& rec) {
      if (!odometry) {
        OdometryOptions opt;
        opt.guess = tracking::InitialGuessMode::imu;
        InitialPoseSource used;
        opt.initial_T_w_c =
            initial_camera_pose(biased, rec.view.t_ns, cfg, used, InitialPoseSource::gravity);
        odometry.emplace(cfg, rec.camera, opt);
      }
      feeder.feed_until(rec.view.t_ns, *odometry);
      frames.push_back(odometry->track(rec.view));
    });
    return std::make_pair(frames, odometry->counters());
  };
  const auto [with_gicp, with_counters] = track(cfg_);
  const double ate_gicp = testing::camera_ate(motion_, with_gicp, cfg_).stats.rmse;
  cfg_.tracking.max_correction_m = 0.0;
  cfg_.tracking.reinit_after_lost_frames = 0;  // no map restart: dead reckoning throughout
  const auto [imu_only, imu_counters] = track(cfg_);
  EXPECT_EQ(with_counters.lost, 0);
  EXPECT_EQ(imu_counters.tracked, 0);
  const double ate_imu = testing::camera_ate(motion_, imu_only, cfg_).stats.rmse;
  std::printf("ATE rmse: with GICP %.4f m, IMU only %.4f m\n", ate_gicp, ate_imu);
  EXPECT_LT(ate_gicp, 0.5 * ate_imu);
  EXPECT_LT(ate_gicp, 0.03);
}

TEST_F(SimulatedOffice, LostFramesAreImuPropagatedAndTrackingResumes) {
  constexpr std::uint64_t kGapBegin = 70, kGapEnd = 76;  // 6 frames (0.3 s) without depth
  OdometryOptions opt;
  opt.guess = tracking::InitialGuessMode::imu;
  std::optional<Odometry> odometry;
  ImuFeeder feeder(motion_.imu);
  std::vector<TrackedFrame> frames;
  std::vector<std::int64_t> keyframe_t_ns;
  io::for_each_recorded_frame(path_, [&](const io::RecordedFrame& rec) {
    const std::int64_t t_ns = rec.view.t_ns;
    if (!odometry) {
      InitialPoseSource used;
      opt.initial_T_w_c = initial_camera_pose(motion_, t_ns, cfg_, used);
      odometry.emplace(cfg_, rec.camera, opt);
    }
    feeder.feed_until(t_ns, *odometry);
    const bool in_gap = rec.index >= kGapBegin && rec.index < kGapEnd;
    RgbdView frame = rec.view;
    if (in_gap) frame.depth_encoding = DepthEncoding::none;  // no measurement anywhere
    frames.push_back(odometry->track(frame));
    // A keyframe may be published moving_window_frames late: keep its own stamp.
    keyframe_t_ns.push_back(frames.back().keyframe ? odometry->tracker().last_keyframe().t_ns : 0);
  });
  ASSERT_EQ(frames.size(), 101u);
  const eval::Trajectory gt = testing::ground_truth_camera(motion_, frames, cfg_);

  // The camera moves enough across the gap that a frozen pose would be far off.
  const double gap_motion_m =
      (gt.poses[kGapEnd].T_w_x.translation() - gt.poses[kGapBegin - 1].T_w_x.translation()).norm();
  ASSERT_GT(gap_motion_m, 0.2);

  for (std::uint64_t i = kGapBegin; i < kGapEnd; ++i) {
    SCOPED_TRACE(i);
    const TrackedFrame& f = frames[i];
    EXPECT_FALSE(f.pose_from_gicp);
    EXPECT_NE(f.status, tracking::TrackingStatus::tracked);
    EXPECT_TRUE(f.imu_guess);
    // No lost frame becomes a keyframe (one published now belongs to a frame before the gap).
    if (f.keyframe) {
      EXPECT_LT(keyframe_t_ns[i], frames[kGapBegin].t_ns);
    }
    EXPECT_TRUE(bit_identical(f.T_w_c, f.T_w_c_guess));  // the pose is the IMU propagation
    // Same world frame as the ground truth (first pose from it): no alignment needed.
    const double err_m = (f.T_w_c.translation() - gt.poses[i].T_w_x.translation()).norm();
    std::printf("lost frame %llu: IMU-propagated position error %.4f m\n",
                static_cast<unsigned long long>(i), err_m);
    EXPECT_LT(err_m, 0.05) << "IMU-propagated position error after " << (i - kGapBegin + 1)
                           << " lost frames";
  }
  EXPECT_EQ(odometry->counters().lost, static_cast<long>(kGapEnd - kGapBegin));
  // No reset from a lost frame: the IMU propagates from the last good frame across the gap.
  EXPECT_EQ(odometry->counters().imu_resets,
            static_cast<long>(frames.size() - (kGapEnd - kGapBegin)));
  // Resumes at once and stays on track.
  for (std::size_t i = kGapEnd; i < frames.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_TRUE(frames[i].pose_from_gicp);
  }
  EXPECT_LT(testing::camera_ate(motion_, frames, cfg_).stats.rmse, 0.03);
}

TEST_F(SimulatedOffice, GravityStartLevelsTheFirstFrameToAFewHundredthsOfADegree) {
  // The recording's IMU starts with the camera, so the half second before the first frame holds
  // a single sample; its noise alone (2.0e-3 m/s^2/sqrt(Hz) at 200 Hz) tilts the start by about
  // 0.2 degrees, which the 3-minute office turned into centimetres of ATE. The rest window
  // reaches past the frame for kMinRestSamples instead.
  std::optional<std::int64_t> first;
  io::for_each_recorded_frame(path_, [&](const io::RecordedFrame& rec) {
    if (!first) first = rec.view.t_ns;
  });
  ASSERT_TRUE(first.has_value());
  const std::int64_t t_first_ns = *first;
  ASSERT_LE(motion_.imu.front().t_ns, t_first_ns);
  ASSERT_GT(motion_.imu[1].t_ns, t_first_ns);
  InitialPoseSource used;
  const geometry::Pose T_w_c =
      initial_camera_pose(motion_, t_first_ns, cfg_, used, InitialPoseSource::gravity);
  ASSERT_EQ(used, InitialPoseSource::gravity);
  const geometry::Pose T_w_c_gt =
      *interpolate_pose(motion_.body_poses, t_first_ns) *
      inertial::InertialFrontendOptions::from(cfg_.imu, cfg_.extrinsics, cfg_.inertial).T_b_c;
  const Eigen::Vector3d up_c = T_w_c.linear().transpose() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d up_c_gt = T_w_c_gt.linear().transpose() * Eigen::Vector3d::UnitZ();
  const double tilt_deg = std::atan2(up_c.cross(up_c_gt).norm(), up_c.dot(up_c_gt)) * 180.0 / M_PI;
  std::printf("first-frame tilt error: %.4f deg\n", tilt_deg);
  EXPECT_LT(tilt_deg, 0.05);
}

TEST_F(SimulatedOffice, SkipFramesStartsLateWithTheEarlierImuFedFirst) {
  // A live tracker that finds its first frame late (toolchain/bench-start-sweep replays starts
  // 1-10 frames late): the skipped frames are not tracked, the IMU samples before the first
  // tracked frame all go in, and the start is still levelled from the accelerometer at rest.
  const ReplayResult all = replay(tracking::InitialGuessMode::imu);
  ReplayOptions opt;
  opt.skip_frames = 7;
  const ReplayResult late = replay_recording(path_, cfg_, opt);
  ASSERT_EQ(late.frames.size(), all.frames.size() - 7);
  EXPECT_EQ(late.frames_skipped_at_start, 7);
  EXPECT_EQ(all.frames_skipped_at_start, 0);
  EXPECT_EQ(late.frames.front().t_ns, all.frames[7].t_ns);
  EXPECT_EQ(late.frames.back().t_ns, all.frames.back().t_ns);
  EXPECT_EQ(late.imu_samples_fed, motion_.imu.size());
  EXPECT_EQ(late.initial_pose, InitialPoseSource::gravity);
  EXPECT_LT(testing::camera_ate(motion_, late.frames, cfg_).stats.rmse, 0.03);

  opt.skip_frames = static_cast<std::int64_t>(all.frames.size());
  try {
    replay_recording(path_, cfg_, opt);
    ADD_FAILURE() << "every frame skipped: expected a RecordingError";
  } catch (const RecordingError& e) {
    EXPECT_NE(std::string(e.what()).find(path_), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("skipped"), std::string::npos) << e.what();
  }
}

TEST(InterpolatePose, ExactMidpointAndOutOfRange) {
  std::vector<StampedPose> poses(2);
  poses[0].t_ns = 1000;
  poses[1].t_ns = 2000;
  poses[1].T_w_x = geometry::make_pose(Eigen::Vector3d(0, 0, 0.5), Eigen::Vector3d(2, 0, 0));
  EXPECT_TRUE(interpolate_pose(poses, 1000)->isApprox(poses[0].T_w_x));
  const geometry::Pose mid = *interpolate_pose(poses, 1500);
  EXPECT_NEAR(mid.translation().x(), 1.0, 1e-12);
  EXPECT_NEAR(geometry::rotation_angle(mid.linear()), 0.25, 1e-12);
  EXPECT_FALSE(interpolate_pose(poses, 999).has_value());
  EXPECT_FALSE(interpolate_pose(poses, 2001).has_value());
  EXPECT_FALSE(interpolate_pose(poses, 1500, 500).has_value());  // gap too long
  EXPECT_FALSE(interpolate_pose({}, 0).has_value());
}

}  // namespace
}  // namespace vigs::pipeline
