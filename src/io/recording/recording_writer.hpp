#pragma once
// Writes a VIGS recording (io/recording_topics.hpp): camera_info, colour and depth with every
// frame, IMU samples, the ground-truth body pose and (simulator) person mask, each as its ROS 2
// message (CDR) on its declared topic. The simulator (sim/mcap_sink.hpp) and the dataset importers
// (io/import/) write through it, so every producer writes the same layout.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/geometry/se3.hpp"
#include "core/types/imu_sample.hpp"
#include "core/types/pinhole_camera.hpp"
#include "io/mcap/mcap_writer.hpp"

namespace vigs::io {

struct RecordingWriterOptions {
  std::string depth_encoding = "16UC1";  ///< 16UC1 | 32FC1
  double depth_scale_m = 0.001;          ///< metres per 16UC1 unit (the topic declares mm)
  int zstd_level = 1;
};

class RecordingWriter {
 public:
  /// Writes `path`.partial; close() renames it to `path`, so `path` only ever holds a
  /// complete recording. Throws io::IoError, std::invalid_argument on a bad depth encoding.
  RecordingWriter(const std::string& path, const RecordingWriterOptions& options);

  /// One RGB-D frame: CameraInfo, then the colour image (rgb8, or mono8 when `gray`), then the
  /// depth (metres, 0 = no measurement) in the configured encoding, all stamped t_ns.
  void frame(std::int64_t t_ns, const PinholeCamera& camera, std::span<const std::uint8_t> color,
             bool gray, std::span<const float> depth_m);
  /// One IMU sample with the diagonal noise variances it is published with; a negative
  /// gyro_variance marks the angular velocity as not measured (ROS: covariance[0] = -1).
  void imu(const ImuSample& sample, double gyro_variance_rps2, double accel_variance_mps4);
  /// Ground-truth mask of the frame at t_ns (io::topics::kDynamicMask): mono8, 255 where a
  /// moving person is the closest surface, width x height row-major. Its channel is added at the
  /// first call, so recordings without masks (importers) declare no empty mask topic.
  /// Throws std::invalid_argument when the mask does not hold width x height pixels.
  void dynamic_mask(std::int64_t t_ns, int width_px, int height_px,
                    std::span<const std::uint8_t> mask);
  /// Ground-truth body pose T_w_b.
  void ground_truth(std::int64_t t_ns, const geometry::Pose& T_w_b);
  /// Writes the summary and renames the file into place. Throws io::IoError.
  void close();

  [[nodiscard]] const mcap::McapWriterStats& stats() const { return writer_.stats(); }

 private:
  RecordingWriterOptions opt_;
  std::string path_;
  mcap::McapWriter writer_;
  std::uint16_t ch_info_, ch_rgb_, ch_depth_, ch_imu_, ch_gt_;
  std::uint16_t ch_mask_ = 0;  ///< 0 until the first dynamic_mask()
  std::vector<std::uint8_t> scratch_;
};

}  // namespace vigs::io
