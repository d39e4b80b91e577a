#pragma once
// TUM RGB-D dataset folders (https://cvg.cit.tum.de/data/datasets/rgbd-dataset/file_formats)
// converted into a VIGS recording (io/recording_topics.hpp):
//   rgb.txt, depth.txt       "timestamp filename" per line (PNG: 8-bit colour, 16-bit depth
//                            in 1/5000 m, 0 = no measurement)
//   groundtruth.txt          "timestamp tx ty tz qx qy qz qw" (optional): the colour camera's
//                            pose in the motion-capture world
//   accelerometer.txt        "timestamp ax ay az" in m/s^2 (optional): the Kinect's
//                            accelerometer, no gyroscope
// Timestamps are seconds with up to 9 decimals, parsed exactly into int64 nanoseconds. Lines
// starting with '#' and blank lines are skipped; any other malformed line is an error naming
// the file and line.
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry/se3.hpp"
#include "core/types/pinhole_camera.hpp"

namespace vigs::io {

class ImportError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct StampedFile {
  std::int64_t t_ns = 0;
  std::string path;  ///< as written in the list, relative to the dataset folder
};

struct StampedPose {
  std::int64_t t_ns = 0;
  geometry::Pose T_w_c = geometry::Pose::Identity();
};

struct StampedVector3 {
  std::int64_t t_ns = 0;
  double xyz[3] = {};
};

/// "1305031102.175304" -> 1305031102175304000. Throws ImportError (`where` names the field).
std::int64_t parse_seconds_to_ns(const std::string& text, const std::string& where);

/// Throw ImportError "FILE:LINE: ..." on a malformed line or an unreadable file; stamps must
/// not decrease.
std::vector<StampedFile> read_tum_file_list(const std::string& path);
std::vector<StampedPose> read_tum_groundtruth(const std::string& path);
std::vector<StampedVector3> read_tum_accelerometer(const std::string& path);

struct TumImportOptions {
  std::filesystem::path dir;  ///< the dataset folder (rgb.txt, depth.txt, ...)
  std::string out;            ///< the recording to write (.mcap)
  /// Intrinsics; width and height 0 = the first colour image's size.
  PinholeCamera camera;
  double depth_units_per_m = 5000.0;          ///< TUM's depth PNG scale
  std::int64_t max_pair_gap_ns = 20'000'000;  ///< colour-depth association (associate.py)
  double accel_variance_mps4 = 0.0;           ///< published with each accelerometer sample
};

struct TumImportStats {
  int frames = 0;                    ///< colour images written with their depth
  int colour_without_depth = 0;      ///< no depth within max_pair_gap_ns: skipped
  int ground_truth = 0;              ///< poses written
  int accelerometer = 0;             ///< samples written
  std::int64_t max_pair_gap_ns = 0;  ///< largest colour-depth gap among the written frames
};

/// Writes options.out (through a .partial file renamed into place). Each colour image is paired
/// with the nearest unused depth image within max_pair_gap_ns, and both are stamped with the
/// colour image's time. Depth is written as 32FC1 metres (raw / depth_units_per_m). Ground
/// truth goes to the body-pose topic as the camera's pose (use identity camera extrinsics),
/// and accelerometer samples to the IMU topic with the angular velocity marked as not measured.
/// Throws ImportError naming the file (and line) on bad input.
TumImportStats import_tum_rgbd(const TumImportOptions& options);

}  // namespace vigs::io
