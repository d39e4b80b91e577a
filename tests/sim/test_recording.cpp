#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <map>

#include "../common/scaled_camera.hpp"
#include "../common/temp_files.hpp"
#include "io/mcap/mcap_reader.hpp"
#include "io/recording/recorded_frames.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/typed_io.hpp"
#include "sim/mcap_sink.hpp"
#include "sim/simulator.hpp"

namespace vigs::sim {
namespace {

/// Collects what a sink receives.
class MemorySink : public SimSink {
 public:
  void frame(std::int64_t t_ns, const PinholeCamera&, const RgbdFrame& f) override {
    frame_t.push_back(t_ns);
    last_depth = f.depth_m;
    masks.push_back(f.dynamic_mask);
    events.push_back({t_ns, 2});
  }
  void imu(const ImuSample& s) override {
    imu_samples.push_back(s);
    events.push_back({s.t_ns, 0});
  }
  void ground_truth(std::int64_t t_ns, const geometry::Pose& T) override {
    gt_t.push_back(t_ns);
    gt.push_back(T);
    events.push_back({t_ns, 1});
  }
  /// (stamp, kind: 0 imu, 1 ground truth, 2 frame) in call order.
  std::vector<std::pair<std::int64_t, int>> events;
  std::vector<std::int64_t> frame_t, gt_t;
  std::vector<ImuSample> imu_samples;
  std::vector<geometry::Pose> gt;
  std::vector<float> last_depth;
  std::vector<std::vector<std::uint8_t>> masks;  ///< every frame's ground-truth person mask
};

/// Passes every call on to two sinks.
class TeeSink : public SimSink {
 public:
  TeeSink(SimSink& x, SimSink& y) : x_(x), y_(y) {}
  void frame(std::int64_t t, const PinholeCamera& c, const RgbdFrame& f) override {
    x_.frame(t, c, f);
    y_.frame(t, c, f);
  }
  void imu(const ImuSample& s) override {
    x_.imu(s);
    y_.imu(s);
  }
  void ground_truth(std::int64_t t, const geometry::Pose& T) override {
    x_.ground_truth(t, T);
    y_.ground_truth(t, T);
  }

 private:
  SimSink& x_;
  SimSink& y_;
};

config::RobotConfig one_second() {
  config::RobotConfig cfg;
  cfg.sim.preset = "apartment";
  cfg.sim.humans = 12;
  cfg.sim.seconds = 1.0;
  return cfg;
}

TEST(Simulator, StreamsAtTheConfiguredRatesInTimeOrderAndDeterministically) {
  Simulator sim(one_second());
  MemorySink a, b;
  const SimStats st = sim.run(a);
  Simulator(one_second()).run(b);
  EXPECT_EQ(st.frames, 21);  // 0, 50, ..., 1000 ms
  EXPECT_EQ(st.imu_samples, 201);
  ASSERT_EQ(a.frame_t.size(), 21u);
  EXPECT_EQ(a.frame_t[1], 50'000'000);
  EXPECT_EQ(a.imu_samples[1].t_ns, 5'000'000);
  EXPECT_EQ(a.gt_t.size(), 201u);
  for (std::size_t i = 0; i < a.imu_samples.size(); ++i) {
    EXPECT_EQ(std::memcmp(&a.imu_samples[i], &b.imu_samples[i], sizeof(ImuSample)), 0);
  }
  EXPECT_EQ(a.last_depth, b.last_depth);
  // Time order; at equal stamps IMU, then ground truth, then the frame.
  ASSERT_EQ(a.events.size(), 21u + 2u * 201u);
  for (std::size_t i = 1; i < a.events.size(); ++i) {
    EXPECT_LT(a.events[i - 1], a.events[i]) << i;
  }
  EXPECT_TRUE(a.gt[100].isApprox(sim.body_pose(0.5), 1e-12));
}

TEST(Simulator, WritesAReadableMcapWithEveryTopic) {
  vigs::test::TempFiles files("vigs_sim_test");  // removed however the test ends
  const std::string path = files.path("rec.mcap");
  Simulator sim(one_second());
  McapSinkOptions opt;
  McapSink sink(path, opt);
  MemorySink mem;
  TeeSink tee(sink, mem);
  sim.run(tee);
  sink.close();

  io::mcap::McapReader reader(path);
  std::map<std::string, int> count;
  io::mcap::MessageView m;
  io::ros_msgs::Image depth, mask;
  io::ros_msgs::CameraInfo info;
  io::ros_msgs::PoseStamped pose;
  io::ros_msgs::Imu imu;
  std::string previous_topic;
  while (reader.next(m)) {
    const std::string topic = m.channel->topic;
    ++count[topic];
    bool ok = true;
    if (topic == "/vigs/depth") ok = io::ros_msgs::decode_message(m, depth);
    if (topic == "/vigs/ground_truth/dynamic_mask") {
      ok = io::ros_msgs::decode_message(m, mask);
      EXPECT_EQ(previous_topic, "/vigs/depth");  // right after its frame's depth
      EXPECT_EQ(mask.header.stamp.to_ns(), depth.header.stamp.to_ns());
    }
    previous_topic = topic;
    if (topic == "/vigs/camera_info") ok = io::ros_msgs::decode_message(m, info);
    if (topic == "/vigs/ground_truth/body_pose") ok = io::ros_msgs::decode_message(m, pose);
    if (topic == "/vigs/imu") ok = io::ros_msgs::decode_message(m, imu);
    ASSERT_TRUE(ok) << topic;
  }
  EXPECT_TRUE(reader.issues().empty());
  EXPECT_EQ(count["/vigs/rgb"], 21);
  EXPECT_EQ(count["/vigs/depth"], 21);
  EXPECT_EQ(count["/vigs/camera_info"], 21);
  EXPECT_EQ(count["/vigs/imu"], 201);
  EXPECT_EQ(count["/vigs/ground_truth/body_pose"], 201);
  EXPECT_EQ(count["/vigs/ground_truth/dynamic_mask"], 21);
  EXPECT_EQ(mask.encoding, "mono8");
  EXPECT_EQ(mask.step, 720u);
  EXPECT_EQ(mask.data, mem.masks.back());
  EXPECT_DOUBLE_EQ(info.k[0], 415.69219381653056);
  EXPECT_DOUBLE_EQ(info.k[2], 360.0);
  EXPECT_EQ(depth.encoding, "16UC1");
  ASSERT_EQ(depth.data.size(), 720u * 480u * 2u);
  // The last depth image is the rendered one in millimetres.
  for (std::size_t i = 0; i < mem.last_depth.size(); i += 97) {
    const int mm = depth.data[2 * i] | (depth.data[2 * i + 1] << 8);
    EXPECT_NEAR(mm * 1e-3, mem.last_depth[i], 0.5e-3 + 1e-6);
  }
  EXPECT_EQ(pose.header.stamp.to_ns(), 1'000'000'000);
  EXPECT_DOUBLE_EQ(pose.pose.position.x, mem.gt.back().translation().x());
  EXPECT_DOUBLE_EQ(imu.angular_velocity.z, mem.imu_samples.back().gyro_rps[2]);
}

TEST(Simulator, GrayAnd32FC1DepthThroughTheMcapSink) {
  vigs::test::TempFiles files("vigs_sim_gray");  // removed however the test ends
  const std::string path = files.path("rec.mcap");
  config::RobotConfig cfg = one_second();
  cfg.sim.seconds = 0.1;
  cfg.sim.gray = true;
  Simulator sim(cfg);
  McapSinkOptions opt;
  opt.depth_encoding = "32FC1";
  McapSink sink(path, opt);
  MemorySink mem;
  TeeSink tee(sink, mem);
  sim.run(tee);
  sink.close();
  io::mcap::McapReader reader(path);
  io::mcap::MessageView m;
  io::ros_msgs::Image rgb, depth;
  while (reader.next(m)) {
    bool ok = true;
    if (m.channel->topic == "/vigs/rgb") ok = io::ros_msgs::decode_message(m, rgb);
    if (m.channel->topic == "/vigs/depth") ok = io::ros_msgs::decode_message(m, depth);
    ASSERT_TRUE(ok) << m.channel->topic;
  }
  EXPECT_EQ(rgb.encoding, "mono8");
  EXPECT_EQ(rgb.step, 720u);
  EXPECT_EQ(rgb.data.size(), 720u * 480u);
  EXPECT_EQ(depth.encoding, "32FC1");
  ASSERT_EQ(depth.data.size(), 720u * 480u * 4u);
  std::vector<float> metres(720 * 480);
  std::memcpy(metres.data(), depth.data.data(), depth.data.size());
  EXPECT_EQ(metres, mem.last_depth);  // bit-exact
}

/// The ground-truth person mask comes back from the file with its frame; a reader that does not
/// ask for it sees the frames as before.
TEST(Simulator, PersonMaskRoundTripsThroughTheFrameReader) {
  vigs::test::TempFiles files("vigs_sim_mask");  // removed however the test ends
  const std::string path = files.path("rec.mcap");
  config::RobotConfig cfg = one_second();
  cfg.sim.humans = 60;  // people in view from the start
  vigs::test::use_default_camera_divided(cfg.camera, 3);
  Simulator sim(cfg);
  McapSink sink(path, McapSinkOptions{});
  MemorySink mem;
  TeeSink tee(sink, mem);
  sim.run(tee);
  sink.close();
  ASSERT_EQ(mem.masks.size(), 21u);

  std::size_t frames = 0, frames_with_people = 0;
  io::for_each_recorded_frame(
      path,
      [&](const io::RecordedFrame& f) {
        ASSERT_LT(f.index, mem.masks.size());
        const std::vector<std::uint8_t>& truth = mem.masks[f.index];
        ASSERT_NE(f.dynamic_mask, nullptr) << f.index;
        ASSERT_EQ(truth.size(), static_cast<std::size_t>(f.view.width_px) * f.view.height_px);
        EXPECT_TRUE(std::equal(truth.begin(), truth.end(), f.dynamic_mask)) << f.index;
        EXPECT_TRUE(f.view.has_depth());
        EXPECT_EQ(f.view.t_ns, mem.frame_t[f.index]);
        frames_with_people += std::count(truth.begin(), truth.end(), 255) > 0;
        ++frames;
      },
      std::string(io::topics::kRgb.name), std::string(io::topics::kCameraInfo.name),
      std::string(io::topics::kDepth.name), io::kDepthPairToleranceNs,
      std::string(io::topics::kDynamicMask.name));
  EXPECT_EQ(frames, 21u);
  EXPECT_GT(frames_with_people, 0u);

  std::size_t plain = 0;
  io::for_each_recorded_frame(path, [&](const io::RecordedFrame& f) {
    EXPECT_EQ(f.dynamic_mask, nullptr);
    EXPECT_TRUE(f.view.has_depth());
    ++plain;
  });
  EXPECT_EQ(plain, 21u);
}

}  // namespace
}  // namespace vigs::sim
