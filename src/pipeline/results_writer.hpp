#pragma once
// Writes a replay's RESULTS_DIR as pipeline/results_dir.hpp defines it: trajectory.tum
// (T_w_c of every frame), keyframes.txt (stamps of the frames that became keyframes) and
// stats.json (formatted by the caller: "frames", "wall_s", "fps", "peak_rss_bytes", ...).
// Every file is written to a temporary file next to it and renamed into place, so a reader
// never sees a half-written file. map.ply (3DGS PLY) is written when the replay built a map.
#include <string>

#include "pipeline/lockstep_replay.hpp"

namespace vigs::pipeline {

/// Peak resident set size of this process so far (getrusage ru_maxrss), bytes.
double peak_rss_bytes();

/// Creates `dir` (and parents) if needed and writes trajectory.tum, keyframes.txt, map.ply
/// (when r.map is set) and stats.json (the text `stats_json`), that one last. Throws
/// std::runtime_error (io::IoError for the trajectory) naming the file that could not be written.
void write_results_dir(const std::string& dir, const ReplayResult& r,
                       const std::string& stats_json);

}  // namespace vigs::pipeline
