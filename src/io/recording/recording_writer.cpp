#include "io/recording/recording_writer.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "io/io_error.hpp"
#include "io/recording_topics.hpp"
#include "io/ros_msgs/camera_info.hpp"
#include "io/ros_msgs/image.hpp"
#include "io/ros_msgs/imu.hpp"
#include "io/ros_msgs/pose_stamped.hpp"
#include "io/ros_msgs/typed_io.hpp"

namespace vigs::io {
namespace {

mcap::McapWriterOptions writer_options(const RecordingWriterOptions& o) {
  mcap::McapWriterOptions w;
  w.zstd_level = o.zstd_level;
  w.chunk_size_bytes = 8u << 20;
  return w;
}

}  // namespace

RecordingWriter::RecordingWriter(const std::string& path, const RecordingWriterOptions& options)
    : opt_(options), path_(path), writer_(path + ".partial", writer_options(options)) {
  if (opt_.depth_encoding != "16UC1" && opt_.depth_encoding != "32FC1") {
    throw std::invalid_argument("depth encoding must be 16UC1 or 32FC1, not " +
                                opt_.depth_encoding);
  }
  using namespace ros_msgs;
  ch_info_ = add_channel<CameraInfo>(writer_, topics::kCameraInfo.name);
  ch_rgb_ = add_channel<Image>(writer_, topics::kRgb.name);
  ch_depth_ = add_channel<Image>(writer_, topics::kDepth.name);
  ch_imu_ = add_channel<Imu>(writer_, topics::kImu.name);
  ch_gt_ = add_channel<PoseStamped>(writer_, topics::kBodyPose.name);
}

void RecordingWriter::frame(std::int64_t t_ns, const PinholeCamera& cam,
                            std::span<const std::uint8_t> color, bool gray,
                            std::span<const float> depth_m) {
  using namespace ros_msgs;
  const auto t = static_cast<std::uint64_t>(t_ns);
  CameraInfo info;
  info.header.stamp = Time::from_ns(t_ns);
  info.header.frame_id = topics::kCameraInfo.frame_id;  // = the images' frame id
  info.width = static_cast<std::uint32_t>(cam.width_px);
  info.height = static_cast<std::uint32_t>(cam.height_px);
  info.distortion_model = "plumb_bob";
  info.d = {0, 0, 0, 0, 0};
  info.k = {cam.fx_px, 0, cam.cx_px, 0, cam.fy_px, cam.cy_px, 0, 0, 1};
  info.r = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.p = {cam.fx_px, 0, cam.cx_px, 0, 0, cam.fy_px, cam.cy_px, 0, 0, 0, 1, 0};
  write_message(writer_, ch_info_, t, info, scratch_);

  Image img;
  img.header = info.header;
  img.width = info.width;
  img.height = info.height;
  img.encoding = gray ? "mono8" : "rgb8";
  img.step = info.width * (gray ? 1u : 3u);
  img.data.assign(color.begin(), color.end());
  write_message(writer_, ch_rgb_, t, img, scratch_);

  Image depth;
  depth.header = info.header;
  depth.width = info.width;
  depth.height = info.height;
  depth.encoding = opt_.depth_encoding;
  const std::size_t n = depth_m.size();
  if (opt_.depth_encoding == "16UC1") {
    depth.step = info.width * 2u;
    depth.data.resize(n * 2);
    for (std::size_t i = 0; i < n; ++i) {
      const double raw = std::round(depth_m[i] / opt_.depth_scale_m);
      const auto v = static_cast<std::uint16_t>(std::clamp(raw, 0.0, 65535.0));
      depth.data[2 * i] = static_cast<std::uint8_t>(v & 0xFF);  // little-endian
      depth.data[2 * i + 1] = static_cast<std::uint8_t>(v >> 8);
    }
  } else {
    depth.step = info.width * 4u;
    depth.data.resize(n * 4);
    std::memcpy(depth.data.data(), depth_m.data(), n * 4);  // host is little-endian
  }
  write_message(writer_, ch_depth_, t, depth, scratch_);
}

void RecordingWriter::dynamic_mask(std::int64_t t_ns, int width_px, int height_px,
                                   std::span<const std::uint8_t> mask) {
  using namespace ros_msgs;
  if (width_px <= 0 || height_px <= 0 ||
      mask.size() != static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px))
    throw std::invalid_argument("dynamic mask of " + std::to_string(mask.size()) + " bytes for a " +
                                std::to_string(width_px) + "x" + std::to_string(height_px) +
                                " image");
  if (ch_mask_ == 0) ch_mask_ = add_channel<Image>(writer_, topics::kDynamicMask.name);
  Image img;
  img.header.stamp = Time::from_ns(t_ns);
  img.header.frame_id = topics::kDynamicMask.frame_id;
  img.width = static_cast<std::uint32_t>(width_px);
  img.height = static_cast<std::uint32_t>(height_px);
  img.encoding = "mono8";
  img.step = img.width;
  img.data.assign(mask.begin(), mask.end());
  write_message(writer_, ch_mask_, static_cast<std::uint64_t>(t_ns), img, scratch_);
}

void RecordingWriter::imu(const ImuSample& s, double gyro_variance_rps2,
                          double accel_variance_mps4) {
  using namespace ros_msgs;
  Imu m;
  m.header.stamp = Time::from_ns(s.t_ns);
  m.header.frame_id = topics::kImu.frame_id;
  m.orientation_covariance[0] = -1.0;  // no orientation estimate
  m.angular_velocity = {s.gyro_rps[0], s.gyro_rps[1], s.gyro_rps[2]};
  m.linear_acceleration = {s.accel_mps2[0], s.accel_mps2[1], s.accel_mps2[2]};
  for (int i = 0; i < 3; ++i) {
    m.angular_velocity_covariance[static_cast<std::size_t>(4 * i)] = gyro_variance_rps2;
    m.linear_acceleration_covariance[static_cast<std::size_t>(4 * i)] = accel_variance_mps4;
  }
  if (gyro_variance_rps2 < 0.0) {
    m.angular_velocity_covariance.fill(0.0);
    m.angular_velocity_covariance[0] = -1.0;  // not measured
  }
  write_message(writer_, ch_imu_, static_cast<std::uint64_t>(s.t_ns), m, scratch_);
}

void RecordingWriter::ground_truth(std::int64_t t_ns, const geometry::Pose& T_w_b) {
  using namespace ros_msgs;
  PoseStamped m;
  m.header.stamp = Time::from_ns(t_ns);
  m.header.frame_id = topics::kBodyPose.frame_id;
  const Eigen::Quaterniond q(T_w_b.linear());
  m.pose.position = {T_w_b.translation().x(), T_w_b.translation().y(), T_w_b.translation().z()};
  m.pose.orientation = {q.x(), q.y(), q.z(), q.w()};
  write_message(writer_, ch_gt_, static_cast<std::uint64_t>(t_ns), m, scratch_);
}

void RecordingWriter::close() {
  if (!writer_.is_open()) return;
  writer_.close();
  if (std::rename((path_ + ".partial").c_str(), path_.c_str()) != 0) {
    throw IoError(path_ + ": cannot rename " + path_ +
                  ".partial into place: " + std::strerror(errno));
  }
}

}  // namespace vigs::io
