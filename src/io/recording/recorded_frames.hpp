#pragma once
// Recorded colour frames from an MCAP recording, streamed one at a time as RgbdViews
// (core/types/rgbd_view.hpp): each sensor_msgs/Image on the colour topic ("rgb8" and "mono8"
// viewed in place, "bgr8" converted to RGB) with the intrinsics of the latest
// sensor_msgs/CameraInfo on the info topic (the simulator writes one before every frame), and
// the depth image on the depth topic when it directly follows and its stamp is within
// `depth_tolerance_ns` of the colour's ("16UC1" millimetres or "32FC1" metres, copied out of
// the message into a buffer reused from frame to frame; other encodings or sizes leave the
// frame without depth). Stamps stay integer nanoseconds (header stamps). Given a mask topic
// (the simulator's io::topics::kDynamicMask), each frame also carries the mono8 mask of the
// same stamp, copied into a reused buffer.
#include <cstdint>
#include <functional>
#include <string>

#include "core/types/pinhole_camera.hpp"
#include "core/types/rgbd_view.hpp"
#include "io/mcap/damage_report.hpp"
#include "io/recording_topics.hpp"

namespace vigs::io {

/// Largest |t_depth - t_colour| still paired. Registered depth and colour of one capture carry
/// the same stamp (the simulator, uHumans, the RGB-D driver's pool frames); 1 ms also pairs
/// recorders that stamp the two images separately, and stays far below a frame period
/// (33-50 ms), so a neighbouring frame's depth is never taken.
inline constexpr std::int64_t kDepthPairToleranceNs = 1'000'000;

/// Valid only during the callback: `view` points into the reader's message buffers.
struct RecordedFrame {
  std::uint64_t index = 0;  ///< 0-based position among the colour messages
  PinholeCamera camera;     ///< from the latest CameraInfo
  /// t_ns = the colour image's header stamp; colour rgb8 or mono8; depth u16 (mm) or f32 (m),
  /// or none when not recorded.
  RgbdView view;
  /// With a mask topic: width x height bytes, row-major, 255 where a person is the closest
  /// surface; nullptr when the frame has no mask (or no mask topic was asked for).
  const std::uint8_t* dynamic_mask = nullptr;
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
///
/// `mask_topic` empty (default): a frame is delivered when its depth message (paired or not)
/// arrives, the next colour message does, or the file ends. Otherwise the frame also waits for
/// its mask: delivered once both its depth and its mask have arrived, or at the next colour
/// message or the end. A mask of another stamp is ignored (as if not recorded); one of the
/// frame's stamp that is not mono8 of the frame's size is a std::runtime_error naming the file,
/// topic and byte offset.
McapFrameStats for_each_recorded_frame(
    const std::string& path, const std::function<void(const RecordedFrame&)>& fn,
    const std::string& rgb_topic = std::string(io::topics::kRgb.name),
    const std::string& info_topic = std::string(io::topics::kCameraInfo.name),
    const std::string& depth_topic = std::string(io::topics::kDepth.name),
    std::int64_t depth_tolerance_ns = kDepthPairToleranceNs, const std::string& mask_topic = {});

}  // namespace vigs::io
