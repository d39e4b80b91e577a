#pragma once
// Outputs never destroy inputs. Every command that writes a file or folder calls one of these
// before it opens anything for writing. Identity is the inode (stat st_dev and st_ino), so
// symbolic links, hard links, "./a" vs "a" and bind mounts are all seen through.
#include <string>
#include <vector>

namespace vigs::io {

/// Throws IoError "OUTPUT: is the input file INPUT (same inode); refusing to overwrite it" when
/// `output` exists and is the same file as one of `inputs`. Inputs that do not exist are
/// skipped (their reader reports them).
void refuse_output_over_inputs(const std::string& output, const std::vector<std::string>& inputs);

/// For an output folder that will be replaced whole: throws IoError when `dir` is one of
/// `inputs`, or when an input lies anywhere inside `dir` (replacing the folder would delete it).
void refuse_output_dir_over_inputs(const std::string& dir, const std::vector<std::string>& inputs);

}  // namespace vigs::io
