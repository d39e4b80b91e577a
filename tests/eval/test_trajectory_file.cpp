#include <gtest/gtest.h>

#include "eval/trajectory_file.hpp"

namespace vigs::eval {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_trajectory_text(text, "traj.txt");
  } catch (const TrajectoryFileError& e) {
    return e.what();
  }
  return "";
}

TEST(TrajectoryFile, ParsesTumWithCommentsAndBlankLines) {
  const auto t = parse_trajectory_text(
      "# timestamp tx ty tz qx qy qz qw\n\n1.5 1 2 3 0 0 0 1\n  # yaw 180:\n2.5 1 2 4 0 0 1 0\n",
      "x");
  ASSERT_EQ(t.poses.size(), 2u);
  EXPECT_EQ(t.format, TrajectoryFormat::kTum);
  EXPECT_DOUBLE_EQ(t.poses[1].t_s, 2.5);
  EXPECT_DOUBLE_EQ(t.poses[1].T_w_x.translation().z(), 4.0);
  EXPECT_NEAR(t.poses[1].T_w_x.linear()(0, 0), -1.0, 1e-12);
}

TEST(TrajectoryFile, ParsesKittiWithLineIndexAsTime) {
  const auto t = parse_trajectory_text("1 0 0 5 0 1 0 6 0 0 1 7\n0 -1 0 1 1 0 0 2 0 0 1 3\n", "k");
  ASSERT_EQ(t.poses.size(), 2u);
  EXPECT_EQ(t.format, TrajectoryFormat::kKitti);
  EXPECT_DOUBLE_EQ(t.poses[1].t_s, 1.0);
  EXPECT_DOUBLE_EQ(t.poses[0].T_w_x.translation().y(), 6.0);
}

TEST(TrajectoryFile, MalformedInputNamesFileAndLine) {
  EXPECT_EQ(error_of("1 2 3\n"),
            "traj.txt:1: expected 8 fields (TUM: t tx ty tz qx qy qz qw) or 12 (KITTI 3x4 pose), "
            "got 3");
  EXPECT_EQ(error_of("# c\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n"),
            "traj.txt:3: 7 fields, expected 8 ('t tx ty tz qx qy qz qw')");
  EXPECT_EQ(error_of("1 0 0 0 0 0 0 1\n2 0 abc 0 0 0 0 1\n"),
            "traj.txt:2: field 3 'abc' is not a finite number");
  EXPECT_EQ(error_of("1 0 0 0 0 0 0 0\n"), "traj.txt:1: quaternion (qx qy qz qw) has zero norm");
  EXPECT_EQ(error_of("2 0 0 0 0 0 0 1\n# c\n1 0 0 0 0 0 0 1\n"),
            "traj.txt:3: timestamp goes backwards");
  EXPECT_EQ(error_of("1 0 nan 0 0 0 0 1\n"), "traj.txt:1: field 3 'nan' is not a finite number");
  EXPECT_EQ(error_of("1 0 0 0 0 1 0 0 0 0 1 0\n1 0 x 0 0 1 0 0 0 0 1 0\n"),
            "traj.txt:2: field 3 'x' is not a number");
  EXPECT_EQ(error_of("1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1\n"),
            "traj.txt:2: expected 12 fields like the first data line (kitti), got 11");
  EXPECT_NE(
      error_of("2 0 0 0 0 2 0 0 0 0 1 0\n").find("traj.txt:1: the 3x3 block is not a rotation"),
      std::string::npos);
  EXPECT_EQ(error_of("# only a comment\n"), "traj.txt: no poses in file");
  EXPECT_THROW(load_trajectory_file("/nonexistent/t.txt"), TrajectoryFileError);
}

TEST(TrajectoryFile, LoadsEveryReferenceFile) {
  const std::string dir = std::string(VIGS_SHARED_DATA_DIR) + "/trajectories/";
  for (const char* f : {"KITTI_00_gt.txt", "KITTI_00_ORB.txt", "KITTI_00_SPTAM.txt", "V102.txt",
                        "fr2_desk_ORB.txt", "fr2_desk_groundtruth.txt",
                        "freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-rgbdslam.txt"}) {
    EXPECT_NO_THROW(load_trajectory_file(dir + f)) << f;
  }
}

}  // namespace
}  // namespace vigs::eval
