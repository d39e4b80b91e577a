// `vigs import tum` on a TUM-layout folder written from the simulator, and `vigs import euroc`
// on the shared EuRoC V1_02 data: every value written must come back from the recording.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <vector>

#include "core/config/robot_config.hpp"
#include "inertial/euroc_csv.hpp"
#include "io/image_io.hpp"
#include "io/import/tum_rgbd.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/recording/recorded_frames.hpp"
#include "io/recording_topics.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/typed_io.hpp"
#include "sim/sim_sink.hpp"
#include "sim/simulator.hpp"
#include "tests/common/cli_process.hpp"

namespace vigs::io {
namespace {

namespace fs = std::filesystem;

using test_cli::read_text;
using test_cli::run_status;

class TempFolder {
 public:
  TempFolder() {
    path_ = fs::temp_directory_path() /
            ("vigs_import_" + std::to_string(getpid()) + "_" + std::to_string(counter_++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  [[nodiscard]] const fs::path& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  fs::path path_;
};

/// "%d.%06d" seconds as TUM writes them.
std::string seconds(std::int64_t t_ns) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%lld.%06lld", static_cast<long long>(t_ns / 1'000'000'000),
                static_cast<long long>((t_ns % 1'000'000'000) / 1000));
  return buf;
}

/// Writes the simulator's frames, ground truth and accelerometer as a TUM RGB-D folder: depth
/// PNGs in 1/5000 m, each depth image 4 ms after its colour image (TUM's streams are not
/// synchronised), one colour image without depth at the end.
class TumFolderSink : public sim::SimSink {
 public:
  explicit TumFolderSink(const fs::path& dir) : dir_(dir) {
    fs::create_directories(dir / "rgb");
    fs::create_directories(dir / "depth");
    rgb_ << "# color images\n# timestamp filename\n";
    depth_ << "# depth maps\n# timestamp filename\n";
    gt_ << "# ground truth trajectory\n# timestamp tx ty tz qx qy qz qw\n";
    accel_ << "# accelerometer data\n# timestamp ax ay az\n";
    accel_ << std::setprecision(17);
    gt_ << std::setprecision(17);
  }
  void frame(std::int64_t t_ns, const PinholeCamera& camera, const sim::RgbdFrame& f) override {
    camera_ = camera;
    const std::string name = seconds(t_ns) + ".png";
    ImageU8 color(f.width, f.height, f.gray ? 1 : 3);
    color.data = f.color;
    write_png((dir_ / "rgb" / name).string(), color);
    ImageU16 depth(f.width, f.height, 1);
    for (std::size_t i = 0; i < f.depth_m.size(); ++i) {
      depth.data[i] =
          static_cast<std::uint16_t>(std::min(std::lround(f.depth_m[i] * 5000.0), 65535L));
    }
    const std::int64_t t_depth_ns = t_ns + 4'000'000;
    write_png_u16((dir_ / "depth" / (seconds(t_depth_ns) + ".png")).string(), depth);
    rgb_ << seconds(t_ns) << " rgb/" << name << "\n";
    depth_ << seconds(t_depth_ns) << " depth/" << seconds(t_depth_ns) << ".png\n";
    rgb_stamps.push_back(t_ns);
    colors.push_back(color);
    depths.push_back(depth);
  }
  void imu(const ImuSample& s) override {
    accel.push_back(s);
    accel_ << seconds(s.t_ns) << " " << s.accel_mps2[0] << " " << s.accel_mps2[1] << " "
           << s.accel_mps2[2] << "\n";
  }
  void ground_truth(std::int64_t t_ns, const geometry::Pose& T_w_b) override {
    const Eigen::Quaterniond q(T_w_b.linear());
    gt_ << seconds(t_ns) << " " << T_w_b.translation().x() << " " << T_w_b.translation().y() << " "
        << T_w_b.translation().z() << " " << q.x() << " " << q.y() << " " << q.z() << " " << q.w()
        << "\n";
    ++gt_count;
  }
  void finish() {
    // A last colour image whose depth never came.
    write_png((dir_ / "rgb" / "late.png").string(), colors.back());
    rgb_ << seconds(rgb_stamps.back() + 50'000'000) << " rgb/late.png\n";
    std::ofstream(dir_ / "rgb.txt") << rgb_.str();
    std::ofstream(dir_ / "depth.txt") << depth_.str();
    std::ofstream(dir_ / "groundtruth.txt") << gt_.str();
    std::ofstream(dir_ / "accelerometer.txt") << accel_.str();
  }

  PinholeCamera camera_;
  std::vector<std::int64_t> rgb_stamps;
  std::vector<ImageU8> colors;
  std::vector<ImageU16> depths;
  std::vector<ImuSample> accel;
  int gt_count = 0;

 private:
  fs::path dir_;
  std::ostringstream rgb_, depth_, gt_, accel_;
};

config::RobotConfig tiny_office() {
  config::RobotConfig cfg;
  cfg.camera.width_px = 96;
  cfg.camera.height_px = 64;
  cfg.camera.fx_px = cfg.camera.fy_px = 48.0;
  cfg.camera.cx_px = 48.0;
  cfg.camera.cy_px = 32.0;
  cfg.sim.preset = "office";
  cfg.sim.humans = 2;
  cfg.sim.seconds = 0.5;
  return cfg;
}

TEST(ImportTum, SimulatedFolderRoundTripsThroughTheBinary) {
  TempFolder tmp;
  const fs::path dir = tmp.path() / "tum";
  TumFolderSink tum(dir);
  sim::Simulator(tiny_office()).run(tum);
  tum.finish();
  const PinholeCamera& cam = tum.camera_;
  const std::string out = (tmp.path() / "tum.mcap").string();
  char intrinsics[160];
  std::snprintf(intrinsics, sizeof intrinsics, "%.17g,%.17g,%.17g,%.17g", cam.fx_px, cam.fy_px,
                cam.cx_px, cam.cy_px);
  const std::string log = (tmp.path() / "import.out").string();
  ASSERT_EQ(run_status(std::string(VIGS_BIN) + " import tum " + dir.string() + " --out " + out +
                       " --intrinsics " + intrinsics + " > " + log + " 2>&1"),
            0)
      << read_text(log);
  const std::string summary = read_text(log);
  EXPECT_NE(summary.find("\"frames\": 11"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"colour_without_depth\": 1"), std::string::npos) << summary;
  EXPECT_FALSE(fs::exists(out + ".partial"));

  // Frames: stamped at the colour image, colour bytes as written, depth = raw / 5000 m.
  std::size_t n = 0;
  for_each_recorded_frame(out, [&](const RecordedFrame& f) {
    ASSERT_LT(n, tum.rgb_stamps.size());
    EXPECT_EQ(f.view.t_ns, tum.rgb_stamps[n]);
    EXPECT_EQ(f.camera.width_px, cam.width_px);
    EXPECT_EQ(f.camera.fx_px, cam.fx_px);
    EXPECT_EQ(f.camera.cy_px, cam.cy_px);
    ASSERT_EQ(f.view.depth_encoding, DepthEncoding::f32_metres);
    const ImageU16& raw = tum.depths[n];
    const ImageU8& color = tum.colors[n];
    int mismatched = 0;
    for (int y = 0; y < raw.height; ++y) {
      for (int x = 0; x < raw.width; ++x) {
        const float d = f.view.depth_f32_m[static_cast<std::size_t>(y) * f.view.depth_row_stride +
                                           static_cast<std::size_t>(x)];
        mismatched += d != static_cast<float>(raw.at(x, y) / 5000.0);
        mismatched += f.view.rgb_at(x, y)[1] != color.at(x, y, 1);
      }
    }
    EXPECT_EQ(mismatched, 0) << "frame " << n;
    ++n;
  });
  EXPECT_EQ(n, tum.rgb_stamps.size());

  // Ground truth and accelerometer on their topics, in time order.
  mcap::McapReader reader(out);
  mcap::MessageView m;
  int poses = 0, accel = 0;
  std::uint64_t last_t = 0;
  while (reader.next(m)) {
    EXPECT_GE(m.log_time_ns, last_t);
    last_t = m.log_time_ns;
    if (m.channel->topic == topics::kImu.name) {
      ros_msgs::Imu imu;
      ASSERT_TRUE(ros_msgs::decode_message(m, imu));
      EXPECT_EQ(imu.angular_velocity_covariance[0], -1.0);  // no gyroscope in TUM
      ASSERT_LT(static_cast<std::size_t>(accel), tum.accel.size());
      EXPECT_EQ(static_cast<std::int64_t>(m.log_time_ns),
                tum.accel[static_cast<std::size_t>(accel)].t_ns);
      EXPECT_EQ(imu.linear_acceleration.z,
                tum.accel[static_cast<std::size_t>(accel)].accel_mps2[2]);
      ++accel;
    } else if (m.channel->topic == topics::kBodyPose.name) {
      ++poses;
    }
  }
  EXPECT_TRUE(reader.issues().empty());
  EXPECT_EQ(poses, tum.gt_count);
  EXPECT_EQ(accel, tum.gt_count);  // the simulator writes IMU and ground truth at 200 Hz
}

TEST(ImportTum, BadLinesNameFileAndLine) {
  TempFolder tmp;
  const fs::path dir = tmp.path();
  std::ofstream(dir / "rgb.txt") << "# colour\n1.0 rgb/a.png\n2.x rgb/b.png\n";
  EXPECT_THROW(
      {
        try {
          (void)read_tum_file_list((dir / "rgb.txt").string());
        } catch (const ImportError& e) {
          EXPECT_NE(std::string(e.what()).find("rgb.txt:3"), std::string::npos) << e.what();
          throw;
        }
      },
      ImportError);
  std::ofstream(dir / "groundtruth.txt") << "1.0 0 0 0 0 0 0 1\n1.5 0 0 0 0 0 1\n";
  EXPECT_THROW(
      {
        try {
          (void)read_tum_groundtruth((dir / "groundtruth.txt").string());
        } catch (const ImportError& e) {
          EXPECT_NE(std::string(e.what()).find("groundtruth.txt:2: expected 8 fields"),
                    std::string::npos)
              << e.what();
          throw;
        }
      },
      ImportError);
  EXPECT_EQ(parse_seconds_to_ns("1305031102.175304", "t"), 1305031102175304000LL);
  EXPECT_THROW((void)parse_seconds_to_ns("1.1234567891", "t"), ImportError);
}

TEST(ImportEuroc, SharedV102RoundTripsExactly) {
  const std::string data = std::string(VIGS_SHARED_DATA_DIR) + "/euroc_v102";
  TempFolder tmp;
  const std::string out = (tmp.path() / "euroc.mcap").string();
  const std::string log = (tmp.path() / "import.out").string();
  ASSERT_EQ(run_status(std::string(VIGS_BIN) + " import euroc " + data + " --out " + out + " > " +
                       log + " 2>&1"),
            0)
      << read_text(log);
  const auto imu = inertial::read_euroc_imu_csv(data + "/imu0.csv");
  const auto gt = inertial::read_euroc_groundtruth_csv(data + "/groundtruth.csv");
  mcap::McapReader reader(out);
  mcap::MessageView m;
  std::size_t i = 0, k = 0;
  while (reader.next(m)) {
    if (m.channel->topic == topics::kImu.name) {
      ros_msgs::Imu msg;
      ASSERT_TRUE(ros_msgs::decode_message(m, msg));
      ASSERT_LT(i, imu.size());
      EXPECT_EQ(static_cast<std::int64_t>(m.log_time_ns), imu[i].t_ns);
      EXPECT_EQ(msg.angular_velocity.x, imu[i].gyro_rps[0]);
      EXPECT_EQ(msg.angular_velocity.z, imu[i].gyro_rps[2]);
      EXPECT_EQ(msg.linear_acceleration.y, imu[i].accel_mps2[1]);
      ++i;
    } else if (m.channel->topic == topics::kBodyPose.name) {
      ros_msgs::PoseStamped msg;
      ASSERT_TRUE(ros_msgs::decode_message(m, msg));
      ASSERT_LT(k, gt.size());
      EXPECT_EQ(static_cast<std::int64_t>(m.log_time_ns), gt[k].t_ns);
      EXPECT_EQ(msg.pose.position.x, gt[k].p_w_b_m.x());
      const Eigen::Quaterniond q(msg.pose.orientation.w, msg.pose.orientation.x,
                                 msg.pose.orientation.y, msg.pose.orientation.z);
      EXPECT_LT(q.angularDistance(gt[k].q_w_b), 1e-12);
      ++k;
    }
  }
  EXPECT_TRUE(reader.issues().empty());
  EXPECT_EQ(i, imu.size());
  EXPECT_EQ(k, gt.size());
  EXPECT_GT(i, 7000u);
}

}  // namespace
}  // namespace vigs::io
