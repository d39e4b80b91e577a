#pragma once
// Recorded colour frames from an MCAP recording, streamed one at a time: each sensor_msgs/Image
// on the colour topic ("rgb8", "bgr8" or "mono8", converted to RGB) with the intrinsics of the
// latest sensor_msgs/CameraInfo on the info topic (the simulator writes one before every frame),
// and the depth image on the depth topic with the same stamp, when it directly follows
// ("16UC1" millimetres or "32FC1" metres; other encodings or sizes leave the frame without
// depth).
#include <cstdint>
#include <functional>
#include <string>

#include "core/types/pinhole_camera.hpp"
#include "io/image.hpp"
#include "io/mcap/damage_report.hpp"

namespace vigs::eval {

inline constexpr const char* kRgbTopic = "/vigs/rgb";
inline constexpr const char* kCameraInfoTopic = "/vigs/camera_info";
inline constexpr const char* kDepthTopic = "/vigs/depth";

struct RecordedFrame {
  std::uint64_t index = 0;  ///< 0-based position among the colour messages
  double t_s = 0;           ///< header stamp
  PinholeCamera camera;     ///< from the latest CameraInfo
  io::ImageU8 rgb;          ///< 3 channels
  io::ImageF32 depth_m;     ///< same size, metres, 0 = invalid; empty when not recorded
};

struct McapFrameStats {
  std::uint64_t frames = 0;               ///< colour messages delivered
  std::uint64_t without_camera_info = 0;  ///< colour messages skipped: no CameraInfo yet
  /// Damage the reader found; the frames delivered are those of the intact part. The caller
  /// reports it (or refuses the file).
  io::mcap::DamageReport damage;
};

/// Calls `fn` for every colour frame in file order. Throws io::IoError when the file cannot be
/// opened, and
/// std::runtime_error naming the file and byte offset on undecodable messages, an unsupported
/// encoding or an image whose size differs from its CameraInfo; io::IoError naming the record
/// and field on a CameraInfo out of range (size, non-finite K, fx or fy <= 0) or an image whose
/// step or data cannot hold its width x height (checked in 64 bits).
McapFrameStats for_each_recorded_frame(const std::string& path,
                                       const std::function<void(const RecordedFrame&)>& fn,
                                       const std::string& rgb_topic = kRgbTopic,
                                       const std::string& info_topic = kCameraInfoTopic,
                                       const std::string& depth_topic = kDepthTopic);

}  // namespace vigs::eval
