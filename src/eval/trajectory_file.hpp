#pragma once
// Reading trajectory files for evaluation: TUM (`t tx ty tz qx qy qz qw`) and KITTI
// (12 numbers per line, no timestamps; the line index becomes the timestamp so that the
// usual association pairs pose i with pose i). The format is detected from the first data
// line; '#' starts a comment; blank lines are skipped.
#include <stdexcept>
#include <string>

#include "eval/trajectory.hpp"

namespace vigs::eval {

/// A malformed trajectory file. what() names the file and the 1-based line.
class TrajectoryFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Loads a TUM or KITTI trajectory. Throws TrajectoryFileError on a missing file, a line
/// with the wrong number of fields, a non-numeric or non-finite field, a zero quaternion,
/// a non-rotation 3x3 block, or a TUM timestamp that goes backwards.
Trajectory load_trajectory_file(const std::string& path);

/// Parses trajectory text; `name` is used in error messages.
Trajectory parse_trajectory_text(const std::string& text, const std::string& name);

const char* format_name(TrajectoryFormat f);

}  // namespace vigs::eval
