#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "io/mcap/damage_report.hpp"

namespace vigs::io::oni {

struct McapToOniOptions {
  std::string rgb_topic = "/tesse/left_cam/rgb/image_raw";      ///< rgb8, bgr8 or mono8 Image
  std::string depth_topic = "/tesse/depth_cam/mono/image_raw";  ///< 16UC1 (mm) or 32FC1 (m)
  /// At most this many pairs (83 minutes at 20 Hz). Pairs are streamed to the clip as they
  /// complete: memory stays at a few frames (720x480 is 1.7 MB a frame) whatever the length.
  std::size_t max_frames = 100000;
  std::uint32_t fps = 0;  ///< 0 = from the median spacing of the frame stamps
  /// Clip timestamps from the header stamps (1 ms + stamp - first stamp, in whole us) instead of
  /// uniform at fps, so real-time playback keeps the recording's own frame times.
  bool recorded_stamps = false;
  std::int64_t from_stamp_ns = INT64_MIN;  ///< pairs stamped before this are left out
  std::int64_t to_stamp_ns = INT64_MAX;    ///< pairs stamped after this are left out
};

/// What make_oni_from_mcap did.
struct McapToOniResult {
  std::size_t frames = 0;     ///< frame pairs written
  std::size_t unmatched = 0;  ///< colour or depth images without a partner of equal stamp
  std::uint32_t fps = 0;      ///< fps recorded in the clip
  std::uint32_t width = 0, height = 0;
  /// Damage found in the part read: the clip holds the pairs of the intact part.
  mcap::DamageReport damage;
  std::uint64_t first_stamp_ns = 0;  ///< header stamp of the first pair written
  std::uint64_t last_stamp_ns = 0;   ///< header stamp of the last pair written
};

/// With McapToOniOptions::recorded_stamps: the clip timestamp (us) of a frame stamped `t_ns` in a
/// recording whose first pair is stamped `first_t_ns` (1 ms + the difference, whole us).
[[nodiscard]] constexpr std::uint64_t recorded_timestamp_us(std::int64_t t_ns,
                                                            std::int64_t first_t_ns) {
  return 1000 + static_cast<std::uint64_t>(t_ns - first_t_ns) / 1000;
}

/// Turns the colour and depth images of an MCAP recording (cdr or ros1) into an `.oni` clip that
/// OpenNI2 plays back, so the OpenNI2 driver can run on simulated or uHumans data. Images are
/// paired by equal header stamps. Depth 32FC1 (m) becomes mm (rounded; NaN, inf, <= 0 and
/// > 65.535 m become 0 = no depth); bgr8 is swapped to RGB; mono8 is replicated. Throws IoError
/// (no pairs, sizes that differ, unsupported encodings, unreadable files, `oni_path` being the
/// input file). Damage in the recording is not an error: the pairs before it are written and
/// McapToOniResult::damage says what was found.
McapToOniResult make_oni_from_mcap(const std::string& mcap_path, const std::string& oni_path,
                                   const McapToOniOptions& options = {});

}  // namespace vigs::io::oni
