// `vigs imu play` feeding `vigs imu listen` through a pseudo-terminal (both real processes), and
// the EuRoC IMU CSV reader's errors.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <regex>
#include <string>

#include "../common/temp_files.hpp"
#include "drivers/serial_imu/euroc_imu_csv.hpp"

namespace vigs::drivers {
namespace {

// Removed when the test program exits, passed or failed.
std::string temp_path(const std::string& name) {
  static vigs::test::TempFiles files("imu_cli");
  return files.path(name);
}

std::string read_all(FILE* f) {
  std::string out;
  char buf[4096];
  while (std::fgets(buf, sizeof buf, f) != nullptr) out += buf;
  return out;
}

TEST(EurocImuCsv, ReadsRowsAndNamesFileAndLineOfErrors) {
  const std::string good = temp_path("good.csv");
  std::ofstream(good) << "#t,w,w,w,a,a,a\n100,0.1,0.2,0.3,1,2,3\n200, -1e-3 ,0,0,0,0,9.81\r\n";
  const auto rows = read_euroc_imu_csv(good);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[1].t_ns, 200);
  EXPECT_EQ(rows[1].gyro_rps[0], -1e-3);
  EXPECT_EQ(rows[1].accel_mps2[2], 9.81);
  const std::pair<const char*, const char*> bad[] = {
      {"100,0,0,0,0,0,0\n100,0,0,0,0,0,0\n", ":2: timestamp does not increase"},
      {"#h\n100,0,0,0,0,0\n", ":2: expected 7 columns"},
      {"100,0,0,0,0,x,0\n", ":1: malformed number"},
  };
  for (const auto& [text, message] : bad) {
    const std::string path = temp_path("bad.csv");
    std::ofstream(path) << text;
    try {
      (void)read_euroc_imu_csv(path);
      ADD_FAILURE() << text;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path + message), std::string::npos) << e.what();
    }
  }
}

TEST(ImuCli, PlayFeedsListenThroughAPty) {
  // One second of the real EuRoC IMU.
  const std::string csv = temp_path("imu.csv");
  {
    std::ifstream in(std::string(VIGS_SHARED_DATA_DIR) + "/euroc_v102/imu0.csv");
    std::ofstream out(csv);
    std::string line;
    for (int rows = 0; rows <= 200 && std::getline(in, line); ++rows) out << line << "\n";
  }
  const std::string vigs = VIGS_BIN;
  FILE* play = ::popen((vigs + " imu play " + csv + " --delay 1.5").c_str(), "r");
  ASSERT_NE(play, nullptr);
  char first[512] = {};
  ASSERT_NE(std::fgets(first, sizeof first, play), nullptr);
  std::smatch m;
  const std::string head = first;
  ASSERT_TRUE(std::regex_search(head, m, std::regex("\"pty\": \"([^\"]+)\""))) << head;
  FILE* listen = ::popen((vigs + " imu listen --port " + m[1].str() + " --seconds 4").c_str(), "r");
  ASSERT_NE(listen, nullptr);
  const std::string report = read_all(listen);
  EXPECT_EQ(::pclose(listen), 0) << report;
  const std::string tail = read_all(play);
  EXPECT_EQ(::pclose(play), 0);
  EXPECT_NE(report.find("\"samples\": 200,"), std::string::npos) << report;
  EXPECT_NE(report.find("\"bad_checksum\": 0,"), std::string::npos) << report;
  EXPECT_NE(report.find("\"sample_counter_gap\": 0,"), std::string::npos) << report;
  EXPECT_NE(tail.find("\"bytes_written\": 8400"), std::string::npos) << tail;  // 200 x 42
}

}  // namespace
}  // namespace vigs::drivers
