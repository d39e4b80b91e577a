// Hostile recordings: crafted MCAPs (valid CRCs) with one bad field, damaged copies of a real
// simulated recording, and a simulate stopped by SIGTERM. Each ends in a correct result or a
// clear error naming the file and field, exit code 1; never a signal.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <thread>

#include "io/mcap/mcap_reader.hpp"
#include "mapping/ply_io.hpp"
#include "tests/hostile/hostile_util.hpp"

namespace vigs::hostile {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// TUM estimate at the crafted frames' stamps (x = i m, identity rotation).
void write_estimate(const std::string& path, int n) {
  std::string text;
  for (int i = 0; i < n; ++i)
    text += std::to_string(1.0 + 0.05 * i) + " " + std::to_string(i) + " 0 0 0 0 0 1\n";
  write_text(path, text);
}

const auto kMoving = [](int i, CraftedFrame& f) { f.pose.pose.position.x = i; };

TEST(HostileRecording, HugeCameraInfoWidthIsAnErrorNotASegfault) {
  // width 0x55555556 x 3 channels wraps to 2 in 32 bits: the step check used to pass and the
  // copy ran off the 2-byte buffer (SIGSEGV in replay and eval run).
  TempDir dir;
  const std::string rec = dir.file("wide.mcap");
  write_recording(rec, 3, [](int i, CraftedFrame& f) {
    kMoving(i, f);
    f.info.width = f.rgb.width = f.depth.width = 0x55555556u;
    f.info.height = f.rgb.height = f.depth.height = 1;
    f.rgb.step = 0x55555556u * 3u;  // 2
    f.rgb.data.assign(2, 0);
  });
  const VigsRun replay = vigs(dir, "replay " + rec + " --out " + dir.file("res") + " --quiet");
  EXPECT_EQ(replay.status, 1) << replay.err;
  EXPECT_NE(replay.err.find("wide.mcap: /vigs/camera_info message at byte"), std::string::npos)
      << replay.err;
  EXPECT_NE(replay.err.find("width = 1431655766 is out of range"), std::string::npos) << replay.err;

  // eval run reads the frames for PSNR/SSIM when the results hold a map.
  std::filesystem::create_directories(dir.file("results"));
  write_estimate(dir.file("results/trajectory.tum"), 3);
  mapping::GaussianMap map;
  map.resize(1);
  map.quat_wxyz[0] = 1.0f;
  mapping::write_gaussian_ply(dir.file("results/map.ply"), map);
  const VigsRun eval =
      vigs(dir, "eval run " + dir.file("results") + " --gt " + rec + " --no-plots");
  EXPECT_EQ(eval.status, 1) << eval.err;
}

TEST(HostileRecording, ZeroFocalLengthIsRefused) {
  TempDir dir;
  const std::string rec = dir.file("fx0.mcap");
  write_recording(rec, 3, [](int, CraftedFrame& f) { f.info.k[0] = 0.0; });
  const VigsRun r = vigs(dir, "replay " + rec + " --out " + dir.file("res") + " --quiet");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("fx (K[0]) = 0.000000 px is out of range"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir.file("res")));
}

TEST(HostileRecording, ShortImageDataIsRefused) {
  TempDir dir;
  const std::string rec = dir.file("short.mcap");
  write_recording(rec, 2, [](int, CraftedFrame& f) { f.rgb.data.resize(10); });
  const VigsRun r = vigs(dir, "replay " + rec + " --out " + dir.file("res") + " --quiet");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("/vigs/rgb message at byte"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("data holds 10 bytes but step x height = 144"), std::string::npos) << r.err;
}

TEST(HostileRecording, NanGroundTruthIsAnErrorNamingTheRecord) {
  TempDir dir;
  const std::string rec = dir.file("nan_gt.mcap");
  write_recording(rec, 5, [](int i, CraftedFrame& f) {
    kMoving(i, f);
    if (i == 3) f.pose.pose.position.y = kNaN;
  });
  write_estimate(dir.file("est.tum"), 5);
  const VigsRun r = vigs(dir, "eval ate --gt " + rec + " --est " + dir.file("est.tum"));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("/vigs/ground_truth/body_pose message at byte"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("pose (position xyz, orientation xyzw)[1] is not finite (nan)"),
            std::string::npos)
      << r.err;
}

TEST(HostileRecording, InfiniteImuSampleIsAnErrorNamingTheRecord) {
  TempDir dir;
  const std::string rec = dir.file("inf_imu.mcap");
  write_recording(rec, 3, [](int i, CraftedFrame& f) {
    if (i == 1) f.imu.linear_acceleration.x = std::numeric_limits<double>::infinity();
  });
  const VigsRun r = vigs(dir, "replay " + rec + " --out " + dir.file("res") + " --quiet");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("/vigs/imu message at byte"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("linear_acceleration[0] is not finite (inf)"), std::string::npos) << r.err;
}

/// A crafted 40-frame recording cut at 60 %: no summary, the reader stops at the cut.
std::string truncated_copy(const TempDir& dir, int frames = 40) {
  const std::string full = dir.file("full.mcap"), cut = dir.file("cut.mcap");
  write_recording(full, frames, kMoving);
  std::filesystem::copy_file(full, cut);
  std::filesystem::resize_file(cut, std::filesystem::file_size(full) * 6 / 10);
  return cut;
}

TEST(DamagedRecording, EvalAteSaysSoAndHowMuchItUsed) {
  TempDir dir;
  const std::string cut = truncated_copy(dir);
  write_estimate(dir.file("est.tum"), 40);
  const VigsRun r = vigs(dir, "eval ate --gt " + cut + " --est " + dir.file("est.tum"));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("damaged recording (truncated at byte"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("poses up to t ="), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("\"input_damage\": {\"gt\": {\"issues\": "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\"est\": null"), std::string::npos) << r.out;
}

TEST(DamagedRecording, IntactRecordingHasNoDamageInTheJson) {
  TempDir dir;
  const std::string rec = dir.file("ok.mcap");
  write_recording(rec, 10, kMoving);
  write_estimate(dir.file("est.tum"), 10);
  const VigsRun r = vigs(dir, "eval ate --gt " + rec + " --est " + dir.file("est.tum"));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("damaged"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("\"input_damage\": {\"gt\": null, \"est\": null}"), std::string::npos)
      << r.out;
}

TEST(DamagedRecording, McapOniSaysSoAndHowMuchItUsed) {
  TempDir dir;
  const std::string cut = truncated_copy(dir);
  const VigsRun r = vigs(dir, "mcap oni " + cut + " " + dir.file("out.oni") +
                                  " --rgb-topic /vigs/rgb --depth-topic /vigs/depth");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("damaged recording (truncated at byte"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("frame pairs up to stamp"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("\"input_damage\": {\"issues\": "), std::string::npos) << r.out;
}

TEST(DamagedRecording, EvalRunSaysSoInItsJsonAndReport) {
  TempDir dir;
  const std::string cut = truncated_copy(dir);
  std::filesystem::create_directories(dir.file("results"));
  write_estimate(dir.file("results/trajectory.tum"), 40);
  const VigsRun r = vigs(dir, "eval run " + dir.file("results") + " --gt " + cut +
                                  " --no-plots --estimate-frame body");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("damaged recording (truncated at byte"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("\"input_damage\": {\"issues\": "), std::string::npos) << r.out;
  EXPECT_NE(read_text(dir.file("results/report.md")).find("damaged recording"), std::string::npos);
}

// ---- a real simulated recording: SIGTERM, replay, truncation --------------------------------

class SimulatedRecording : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    write_text(dir_->file("small.yaml"),
               "camera:\n  width_px: 240\n  height_px: 160\n  fx_px: 138.56406460551018\n"
               "  fy_px: 138.56406460551018\n  cx_px: 120.0\n  cy_px: 80.0\n"
               "tracking:\n  pixel_stride: 2\n");
    // Long enough that it is still running when the signal comes (2 cores, loaded).
    const std::string rec = dir_->file("sim.mcap");
    const pid_t pid = ::fork();
    if (pid == 0) {
      const std::string cfg = dir_->file("small.yaml"), log = dir_->file("sim.log");
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      ::execl(VIGS_BIN, VIGS_BIN, "simulate", "--config", cfg.c_str(), "--seconds", "120",
              "--humans", "0", "--quiet", "--out", rec.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    // Wait for a few frames in the partial file (the first chunk is written after 1 s of log
    // time), then stop it.
    const auto t0 = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(240)) {
      std::error_code ec;
      if (std::filesystem::file_size(rec + ".partial", ec) > 4'000'000 && !ec) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ::kill(pid, SIGTERM);
    int status = 0;
    ::waitpid(pid, &status, 0);
    sim_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static TempDir* dir_;
  static int sim_status_;
};
TempDir* SimulatedRecording::dir_ = nullptr;
int SimulatedRecording::sim_status_ = -1;

TEST_F(SimulatedRecording, SigtermedSimulateLeavesAReplayableRecording) {
  const std::string rec = dir_->file("sim.mcap");
  const std::string log = read_text(dir_->file("sim.log"));
  EXPECT_EQ(sim_status_, 1) << log;  // not 128 + SIGTERM: the handler let it finish
  EXPECT_NE(log.find("stopped by SIGTERM after"), std::string::npos) << log;
  EXPECT_NE(log.find("\"stopped_by_signal\": \"SIGTERM\""), std::string::npos) << log;
  ASSERT_TRUE(std::filesystem::exists(rec)) << log;
  EXPECT_FALSE(std::filesystem::exists(rec + ".partial"));
  {
    io::mcap::McapReader reader(rec);
    io::mcap::MessageView m;
    std::size_t n = 0;
    while (reader.next(m)) ++n;
    EXPECT_TRUE(reader.has_summary());
    EXPECT_TRUE(reader.issues().empty()) << reader.issues().front().message;
    EXPECT_GT(n, 10u);
  }
  const VigsRun r = vigs(*dir_, "replay " + rec + " --config " + dir_->file("small.yaml") +
                                    " --frames 4 --quiet --out " + dir_->file("res_sig"));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir_->file("res_sig/trajectory.tum")));
}

TEST_F(SimulatedRecording, ReplayRefusesATruncatedCopyUnlessAllowTruncated) {
  const std::string rec = dir_->file("sim.mcap"), cut = dir_->file("sim_cut.mcap");
  ASSERT_TRUE(std::filesystem::exists(rec));
  std::filesystem::copy_file(rec, cut, std::filesystem::copy_options::overwrite_existing);
  std::filesystem::resize_file(cut, std::filesystem::file_size(rec) * 6 / 10);
  const std::string args =
      "replay " + cut + " --config " + dir_->file("small.yaml") + " --frames 4 --quiet --out ";
  const VigsRun refused = vigs(*dir_, args + dir_->file("res_cut"));
  EXPECT_EQ(refused.status, 1) << refused.err;
  EXPECT_NE(refused.err.find("damaged recording (truncated"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find("--allow-truncated"), std::string::npos) << refused.err;

  const VigsRun allowed = vigs(*dir_, args + dir_->file("res_cut") + " --allow-truncated");
  EXPECT_EQ(allowed.status, 0) << allowed.err;
  EXPECT_NE(allowed.err.find("damaged recording (truncated at byte"), std::string::npos)
      << allowed.err;
  EXPECT_NE(allowed.err.find("used 4 frames"), std::string::npos) << allowed.err;
  const std::string stats = read_text(dir_->file("res_cut/stats.json"));
  EXPECT_NE(stats.find("\"input_damage\": {\"issues\": "), std::string::npos) << stats;
}

TEST_F(SimulatedRecording, ReplayIntoAReusedFolderLeavesNoStaleFile) {
  const std::string rec = dir_->file("sim.mcap"), out = dir_->file("reused");
  ASSERT_TRUE(std::filesystem::exists(rec));
  std::filesystem::create_directories(out + "/plots");
  for (const char* name : {"trajectory.tum", "map.ply", "report.md", "plots/ate.png"})
    write_text(out + "/" + name, "stale");
  const VigsRun r = vigs(*dir_, "replay " + rec + " --config " + dir_->file("small.yaml") +
                                    " --frames 3 --quiet --out " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(read_text(out + "/trajectory.tum"), "stale");
  for (const char* name : {"map.ply", "report.md", "plots"})
    EXPECT_FALSE(std::filesystem::exists(out + "/" + name)) << name;
  for (const auto& e : std::filesystem::directory_iterator(dir_->path()))
    EXPECT_EQ(e.path().filename().string().find(".reused.tmp-"), std::string::npos) << e.path();
}

}  // namespace
}  // namespace vigs::hostile
