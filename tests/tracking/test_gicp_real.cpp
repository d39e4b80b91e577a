// GICP on real frames: ICL-NUIM livingroom1 frames 0 -> 2 against the ground truth, and a
// uHumans2 frame against itself under a known offset.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "io/image_io.hpp"
#include "tracking/gicp.hpp"
#include "tracking/preprocess.hpp"

namespace vigs::tracking {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;
const std::string kIcl = std::string(VIGS_SHARED_DATA_DIR) + "/icl_nuim_livingroom1/";
const std::string kUh = std::string(VIGS_SHARED_DATA_DIR) + "/uhumans2_frames/";

// trajectory.log: per frame one header line, then the 4x4 camera-to-world matrix.
std::vector<geometry::Pose> read_icl_trajectory(const std::string& path) {
  std::ifstream in(path);
  std::vector<geometry::Pose> poses;
  int a = 0, b = 0, c = 0;
  while (in >> a >> b >> c) {
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      for (int k = 0; k < 4; ++k) {
        in >> m(r, k);
      }
    }
    poses.emplace_back(geometry::Pose(m));
  }
  return poses;
}

PinholeCamera icl_camera() {
  return {640, 480, 525.0, 525.0, 319.5, 239.5};
}

struct Frame {
  GaussianCloud cloud;
  KdTree tree;
  DepthToPointsStats stats;
};

void load_icl(int index, FramePreprocessor& pre, Frame& f) {
  char name[32];
  std::snprintf(name, sizeof name, "%05d", index);
  const ImageF32 depth = io::read_depth_m(kIcl + "depth_" + name + ".png", 0.001);
  const ImageU8 rgb = io::read_rgb(kIcl + "color_" + name + ".jpg");
  f.stats = pre.process(depth, rgb, f.cloud, f.tree);
}

TEST(GicpReal, IclNuimFrame0To2FromIdentityWithin7mmAnd03deg) {
  const auto poses = read_icl_trajectory(kIcl + "trajectory.log");
  ASSERT_GE(poses.size(), 3u);
  const geometry::Pose T_2_0_true = poses[2].inverse() * poses[0];
  rt::WorkerTeam team(2);
  FramePreprocessor::Setting ps;  // pixel stride 4, k = 10, normalised ellipse
  FramePreprocessor pre(icl_camera(), ps, team);
  Frame f0, f2;
  load_icl(0, pre, f0);
  load_icl(2, pre, f2);
  EXPECT_GT(f0.cloud.size(), 15000u);
  Gicp gicp;  // defaults
  const GicpResult r =
      gicp.align(CloudTarget{&f2.cloud, &f2.tree}, f0.cloud, geometry::Pose::Identity());
  const geometry::PoseError e = geometry::pose_error(T_2_0_true, r.T_t_s);
  RecordProperty("translation_error_m", std::to_string(e.translation_m));
  RecordProperty("rotation_error_deg", std::to_string(e.rotation_rad / kDeg));
  std::printf("ICL 0->2: |t err| %.5f m, rot err %.4f deg, iters %d, inliers %.3f, eig %.4f, %s\n",
              e.translation_m, e.rotation_rad / kDeg, r.iterations, r.inlier_ratio, r.eigen_ratio,
              std::string(to_string(r.verdict)).c_str());
  EXPECT_LT(e.translation_m, 0.007);
  EXPECT_LT(e.rotation_rad, 0.3 * kDeg);
  EXPECT_EQ(r.verdict, GicpVerdict::converged);
}

// The other pairs of the five frames, for the record (printed; loosely bounded).
TEST(GicpReal, IclNuimFrame0ToOthersFromIdentity) {
  const auto poses = read_icl_trajectory(kIcl + "trajectory.log");
  ASSERT_GE(poses.size(), 5u);
  rt::WorkerTeam team(2);
  FramePreprocessor pre(icl_camera(), FramePreprocessor::Setting{}, team);
  Frame f0;
  load_icl(0, pre, f0);
  Gicp gicp;
  for (int j = 1; j < 5; ++j) {
    Frame fj;
    load_icl(j, pre, fj);
    const geometry::Pose T_j_0_true = poses[static_cast<std::size_t>(j)].inverse() * poses[0];
    const GicpResult r =
        gicp.align(CloudTarget{&fj.cloud, &fj.tree}, f0.cloud, geometry::Pose::Identity());
    const geometry::PoseError e = geometry::pose_error(T_j_0_true, r.T_t_s);
    const geometry::PoseError motion = geometry::pose_error(geometry::Pose::Identity(), T_j_0_true);
    std::printf("ICL 0->%d: |t err| %.2f mm, rot err %.3f deg (motion %.1f mm %.2f deg), %d it\n",
                j, e.translation_m * 1e3, e.rotation_rad / kDeg, motion.translation_m * 1e3,
                motion.rotation_rad / kDeg, r.iterations);
    EXPECT_LT(e.translation_m, 0.01);
    EXPECT_LT(e.rotation_rad, 0.5 * kDeg);
  }
}

TEST(GicpReal, UHumans2FrameLoadsAndAlignsToItselfUnderKnownOffset) {
  const PinholeCamera cam{720, 480, 415.69219381653056, 415.69219381653056, 360.0, 240.0};
  const ImageF32 depth = io::read_depth_m(kUh + "depth_img_0.tiff", 1.0);
  const ImageU8 rgb = io::read_rgb(kUh + "left_img_0.png");
  rt::WorkerTeam team(2);
  FramePreprocessor::Setting ps;
  ps.depth.far_m = 10.0;
  FramePreprocessor pre(cam, ps, team);
  Frame f;
  f.stats = pre.process(depth, rgb, f.cloud, f.tree);
  EXPECT_GT(f.stats.points, 5000);
  EXPECT_EQ(f.stats.sampled, f.stats.points + f.stats.invalid + f.stats.too_near + f.stats.too_far);
  // Source = the same points seen from a camera moved by T_t_s_true^-1.
  const geometry::Pose T_t_s_true =
      geometry::make_pose(Eigen::Vector3d(0.01, -0.02, 0.015), Eigen::Vector3d(0.04, -0.02, 0.03));
  Frame src;
  for (const auto& p : f.cloud.points_m) {
    src.cloud.points_m.push_back((T_t_s_true.inverse() * p.cast<double>()).cast<float>());
  }
  pre.finish(src.cloud, src.tree);
  Gicp gicp;
  const GicpResult r =
      gicp.align(CloudTarget{&f.cloud, &f.tree}, src.cloud, geometry::Pose::Identity());
  const geometry::PoseError e = geometry::pose_error(T_t_s_true, r.T_t_s);
  std::printf("uHumans2 self: |t err| %.6f m, rot err %.5f deg, iters %d, eig %.4f, %s\n",
              e.translation_m, e.rotation_rad / kDeg, r.iterations, r.eigen_ratio,
              std::string(to_string(r.verdict)).c_str());
  EXPECT_LT(e.translation_m, 1e-3);
  EXPECT_LT(e.rotation_rad, 0.05 * kDeg);
  EXPECT_NE(r.verdict, GicpVerdict::diverged);
}

}  // namespace
}  // namespace vigs::tracking
