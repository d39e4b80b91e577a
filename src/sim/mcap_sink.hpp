#pragma once
// Writes the simulator's streams to one MCAP file as ROS 2 messages (CDR), through the
// recording writer (io/recording/recording_writer.hpp):
//   /vigs/camera_info             sensor_msgs/msg/CameraInfo  (with every frame)
//   /vigs/rgb                     sensor_msgs/msg/Image rgb8 (mono8 with --gray)
//   /vigs/depth                   sensor_msgs/msg/Image 16UC1 (mm) or 32FC1 (m)
//   /vigs/imu                     sensor_msgs/msg/Imu, frame "body"
//   /vigs/ground_truth/body_pose  geometry_msgs/msg/PoseStamped T_w_b, frame "world"
//   /vigs/ground_truth/dynamic_mask  sensor_msgs/msg/Image mono8, 255 = a person (after depth)
#include <string>

#include "core/config/robot_config.hpp"
#include "io/recording/recording_writer.hpp"
#include "sim/sim_sink.hpp"

namespace vigs::sim {

struct McapSinkOptions {
  std::string depth_encoding = "16UC1";  ///< 16UC1 | 32FC1
  double depth_scale_m = 0.001;          ///< metres per 16UC1 unit
  int zstd_level = 1;
  config::ImuSettings imu;  ///< for the published noise covariances

  /// What `vigs simulate` writes for `cfg`: sim.depth_encoding, camera.depth_scale_m and the
  /// imu: section, with the default zstd level.
  static McapSinkOptions from(const config::RobotConfig& cfg) {
    McapSinkOptions o;
    o.depth_encoding = cfg.sim.depth_encoding;
    o.depth_scale_m = cfg.camera.depth_scale_m;
    o.imu = cfg.imu;
    return o;
  }
};

class McapSink : public SimSink {
 public:
  /// Writes `path`.partial; close() renames it to `path`, so `path` only ever holds a
  /// complete recording. Throws io::IoError.
  McapSink(const std::string& path, const McapSinkOptions& options);
  void frame(std::int64_t t_ns, const PinholeCamera& camera, const RgbdFrame& frame) override;
  void imu(const ImuSample& sample) override;
  void ground_truth(std::int64_t t_ns, const geometry::Pose& T_w_b) override;
  /// Writes the summary and closes the file. Throws io::IoError.
  void close();
  [[nodiscard]] const io::mcap::McapWriterStats& stats() const { return writer_.stats(); }

 private:
  McapSinkOptions opt_;
  io::RecordingWriter writer_;
};

}  // namespace vigs::sim
