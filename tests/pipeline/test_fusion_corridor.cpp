// A corridor where the fused estimator (tracking.fusion: fused, the default) beats the paper's
// scheme (IMU guess, then reset from GICP). The realistic route of seed 2 with 12 walkers, 60 s
// replayed in lockstep: the route is a walk on the office's corridor grid, and at 36-40 s the
// carrier walks a corridor at 1.2 m/s, then brakes to a stop. With a local map that keeps the
// first points each voxel saw (tracking.local_map_replace_depth_ratio 0: voxels ahead are
// filled from 5-8 m away, where the depth noise is largest), GICP converges short along the
// corridor's axis; `paper` resets its velocity from GICP's pose difference, so each next guess
// starts slower and its estimate stops two seconds early, 3 m short. The same failure took the
// 720x480 route of seed 7 to 1.70 m ATE over 3 minutes (BENCHMARKS.md, fifteenth session).
// `fused` keeps the velocity the accelerometer says, and the corridor's axis follows the IMU.
// With the default local map (a voxel's farthest-seen points give way to nearer ones) GICP no
// longer converges short there, and both schemes track the corridor. Simulated at a third of
// 720x480 (sim_sequence.hpp); the failure is the same there.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>

#include <Eigen/Core>

#include "core/config/robot_config.hpp"
#include "pipeline/lockstep_replay.hpp"
#include "pipeline/recorded_motion.hpp"
#include "tests/pipeline/sim_sequence.hpp"

namespace vigs::pipeline {
namespace {

constexpr double kSeconds = 60.0;
constexpr double kCorridorFromS = 34.0;  // the corridor stretch up to the stop, route seconds
constexpr double kCorridorToS = 40.0;

struct CorridorRun {
  double ate_rmse_m = 0.0, ate_max_m = 0.0;
  double corridor_shortfall_m = 0.0;  ///< true minus estimated distance over the stretch
};

/// The estimate's and the truth's camera positions at the frame nearest `t_s` after start.
std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> positions_at(const ReplayResult& r,
                                                                        const eval::Trajectory& gt,
                                                                        double t_s) {
  if (r.frames.empty()) return std::nullopt;
  const double t0 = static_cast<double>(r.frames.front().t_ns) * 1e-9;
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    if (static_cast<double>(r.frames[i].t_ns) * 1e-9 - t0 >= t_s) {
      return std::make_pair(Eigen::Vector3d(r.frames[i].T_w_c.translation()),
                            Eigen::Vector3d(gt.poses[i].T_w_x.translation()));
    }
  }
  return std::nullopt;
}

/// Replays the recording at `path` with `fusion`: ATE and the shortfall over the corridor.
CorridorRun run(const std::string& path, const config::RobotConfig& cfg,
                const RecordedMotion& motion, FusionMode fusion) {
  ReplayOptions opt;
  opt.fusion = fusion;
  const ReplayResult r = replay_recording(path, cfg, opt);
  const eval::Trajectory gt = testing::ground_truth_camera(motion, r.frames, cfg);
  const eval::AteResult ate = eval::compute_ate(gt, testing::estimate(r.frames), {});
  CorridorRun out;
  out.ate_rmse_m = ate.stats.rmse;
  out.ate_max_m = ate.stats.max;
  const auto a = positions_at(r, gt, kCorridorFromS);
  const auto b = positions_at(r, gt, kCorridorToS);
  EXPECT_TRUE(a && b) << "the replay ends before the corridor";
  if (a && b) {
    out.corridor_shortfall_m = (b->second - a->second).norm() - (b->first - a->first).norm();
  }
  std::printf("%s: ATE rmse %.4f m, max %.3f m; %.1f-%.1f s: %.3f m short\n", to_string(fusion),
              out.ate_rmse_m, out.ate_max_m, kCorridorFromS, kCorridorToS,
              out.corridor_shortfall_m);
  return out;
}

/// The 60 s corridor route, simulated once for both tests.
class FusionCorridor : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    cfg_ = testing::small_office(kSeconds);
    cfg_.sim.seed = 2;
    cfg_.sim.humans = 12;
    cfg_.sim.motion = "realistic";
    dir_ = new testing::TempDir();
    testing::simulate(cfg_, dir_->file("corridor.mcap"));
    motion_ = new RecordedMotion(read_recorded_motion(dir_->file("corridor.mcap")));
  }
  static void TearDownTestSuite() {
    delete motion_;
    delete dir_;
  }
  static CorridorRun run_with(FusionMode fusion, double replace_depth_ratio) {
    config::RobotConfig cfg = cfg_;
    cfg.tracking.local_map.replace_depth_ratio = replace_depth_ratio;
    return run(dir_->file("corridor.mcap"), cfg, *motion_, fusion);
  }
  static inline config::RobotConfig cfg_;
  static inline testing::TempDir* dir_ = nullptr;
  static inline RecordedMotion* motion_ = nullptr;
};

// Measured (odometry, no loop closure, first-seen local map): paper 1.75 m RMSE, 2.65 m max;
// fused 0.089 m, 0.12 m (0.105 m with inertial.fused_extra_accel_random_walk 0.03, 0.093 m
// with that and fused_extra_accel_noise_density 0.2).
TEST_F(FusionCorridor, FusedBeatsThePaperSchemeByFiveTimesWherePaperStopsShort) {
  const CorridorRun paper = run_with(FusionMode::paper, 0.0);
  const CorridorRun fused = run_with(FusionMode::fused, 0.0);
  EXPECT_LT(fused.ate_rmse_m, 0.15);
  EXPECT_LT(fused.ate_max_m, 0.3);
  EXPECT_GT(paper.ate_rmse_m, 5.0 * fused.ate_rmse_m);
  // The mechanism: paper falls short over the corridor stretch, fused does not.
  EXPECT_GT(paper.corridor_shortfall_m, 1.0);
  EXPECT_LT(std::abs(fused.corridor_shortfall_m), 0.3);
}

// Measured with the default local map: paper 0.096 m RMSE, 0.15 m long over the stretch;
// fused 0.081 m, 0.11 m long (0.095 m, 0.14 m with inertial.fused_extra_accel_random_walk
// 0.03; 0.052 m, 0.05 m with that and fused_extra_accel_noise_density 0.2, the defaults until
// 2026-12-05: the larger process noise that keeps real-time starts on track on the 3-minute
// routes lets GICP's weak pull along this corridor's axis in). Without the replacement paper
// stops 3 m short (above).
TEST_F(FusionCorridor, NearerPointsInTheLocalMapKeepGicpFromStoppingShort) {
  const double ratio = config::RobotConfig{}.tracking.local_map.replace_depth_ratio;
  ASSERT_GT(ratio, 0.0);
  const CorridorRun paper = run_with(FusionMode::paper, ratio);
  const CorridorRun fused = run_with(FusionMode::fused, ratio);
  EXPECT_LT(std::abs(paper.corridor_shortfall_m), 0.4);
  EXPECT_LT(paper.ate_rmse_m, 0.2);
  EXPECT_LT(fused.ate_rmse_m, 0.10);
  EXPECT_LT(std::abs(fused.corridor_shortfall_m), 0.2);
}

}  // namespace
}  // namespace vigs::pipeline
