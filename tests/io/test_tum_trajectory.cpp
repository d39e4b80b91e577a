// TUM trajectory files: the reference files in ../shared/data parse, malformed lines are reported
// with their line number, and write -> read is bit-exact and atomic.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io/io_error.hpp"
#include "io/tum_trajectory.hpp"
#include "mcap_test_util.hpp"

namespace vigs::io {
namespace {

const std::string kDir = std::string(VIGS_SHARED_DATA_DIR) + "/trajectories/";

TEST(TumTrajectory, ReadsTheReferenceFiles) {
  const auto gt = read_tum_trajectory(kDir + "fr2_desk_groundtruth.txt");  // 3 comment lines
  ASSERT_EQ(gt.size(), 20957u);
  EXPECT_DOUBLE_EQ(gt[0].t_s, 1311868163.8697);
  EXPECT_DOUBLE_EQ(gt[0].p_w_m.x(), -0.1357);
  EXPECT_DOUBLE_EQ(gt[0].q_w.x(), 0.6453);   // qx
  EXPECT_DOUBLE_EQ(gt[0].q_w.w(), -0.4101);  // qw is the last column
  EXPECT_EQ(read_tum_trajectory(kDir + "fr2_desk_ORB.txt").size(), 2893u);
  const auto v102 = read_tum_trajectory(kDir + "V102.txt");  // exponent notation
  ASSERT_EQ(v102.size(), 807u);
  EXPECT_DOUBLE_EQ(v102[0].t_s, 1.403715529112143517e+09);
}

TEST(TumTrajectory, MalformedLinesNameFileAndLine) {
  auto message = [](std::string_view text) {
    try {
      parse_tum_trajectory(text, "traj.txt");
    } catch (const IoError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("# c\n1 2 3 4 5 6 7 8\n1 2 3\n"),
            "traj.txt:3: 3 fields, expected 8 ('t tx ty tz qx qy qz qw')");
  EXPECT_NE(message("1 2 3 4 5 6 7 x\n").find("traj.txt:1: field 8 'x'"), std::string::npos);
  EXPECT_NE(message("\n\n1 2 3 4 5 6 7 8 9\n").find("traj.txt:3: more than 8 fields"),
            std::string::npos);
  EXPECT_NE(message("1 2 3 4 5 6 7 nan\n").find("not a finite number"), std::string::npos);
  EXPECT_NE(message("1 2 3 4 5 6 7 8abc\n").find("'8abc'"), std::string::npos);
  // KITTI pose files (12 numbers) are not TUM files.
  EXPECT_THROW(read_tum_trajectory(kDir + "KITTI_00_gt.txt"), IoError);
  EXPECT_THROW(read_tum_trajectory(kDir + "no_such_file.txt"), IoError);
  // Blank lines, comments, tabs, commas and CRLF are accepted.
  const auto p = parse_tum_trajectory("  # x\n\n1,2\t3 4 5 6 7 8\r\n+1e1 -2 +3 4 5 6 7 8\n", "t");
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].q_w.w(), 8.0);
  EXPECT_EQ(p[1].t_s, 10.0);
  EXPECT_EQ(p[1].p_w_m, Eigen::Vector3d(-2, 3, 4));
}

TEST(TumTrajectory, WriteReadIsBitExactAndAtomic) {
  std::vector<TumPose> poses;
  for (int i = 0; i < 100; ++i) {
    TumPose p;
    p.t_s = 1311868163.8697 + i * 0.0333333333333;
    p.p_w_m = Eigen::Vector3d(std::sin(i) * 1e3, -1.0 / (i + 3), 1e-17 * i);
    p.q_w = Eigen::Quaterniond(Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d(1, 2, 3).normalized()));
    poses.push_back(p);
  }
  const std::string path = test::temp_path("traj.txt");
  std::ofstream(path) << "previous content\n";
  write_tum_trajectory(path, poses);
  const auto back = read_tum_trajectory(path);
  ASSERT_EQ(back.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_EQ(back[i].t_s, poses[i].t_s);
    EXPECT_EQ(back[i].p_w_m, poses[i].p_w_m);
    EXPECT_EQ(back[i].q_w.coeffs(), poses[i].q_w.coeffs());
  }
  // No temporary files left beside the output.
  int files = 0;
  for (const auto& e :
       std::filesystem::directory_iterator(std::filesystem::path(path).parent_path())) {
    files += e.path().filename().string().rfind("traj.txt", 0) == 0;
  }
  EXPECT_EQ(files, 1);
  EXPECT_THROW(write_tum_trajectory("/nonexistent_dir/t.txt", poses), IoError);
}

}  // namespace
}  // namespace vigs::io
