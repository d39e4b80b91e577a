#pragma once
// Writes a replay's RESULTS_DIR as pipeline/results_dir.hpp defines it: trajectory.tum
// (T_w_c of every frame), keyframes.txt (stamps of the frames that became keyframes) and
// stats.json (formatted by the caller: "frames", "wall_s", "fps", "peak_rss_bytes", ...).
// The folder is built whole in a temporary sibling and swapped into place (io/atomic_dir.hpp),
// so a reused RESULTS_DIR never keeps an earlier run's map.ply, report or plots, and a kill
// never leaves a mix of old and new files. map.ply (3DGS PLY) is written when the replay built
// a map.
#include <filesystem>
#include <functional>
#include <string>

#include "pipeline/lockstep_replay.hpp"

namespace vigs::pipeline {

/// Peak resident set size of this process so far (getrusage ru_maxrss), bytes.
double peak_rss_bytes();

/// Writes trajectory.tum, keyframes.txt, map.ply (when r.map is set) and stats.json (the text
/// `stats_json`) as the folder `dir` (parents created), replacing an earlier RESULTS_DIR there
/// whole; a non-empty folder without trajectory.tum is refused. `also` (optional) then writes
/// more files (report.md and its plots) into the same temporary folder, before the one swap:
/// the folder appears with them or not at all. Throws std::runtime_error (io::IoError for the
/// trajectory and the folder) naming what could not be written, or what `also` threw; either
/// way `dir` is left as it was.
void write_results_dir(const std::string& dir, const ReplayResult& r, const std::string& stats_json,
                       const std::function<void(const std::filesystem::path& tmp)>& also = {});

/// The files of a RESULTS_DIR written into the existing folder `root` (each atomically), for
/// writers that build the folder themselves inside io::replace_dir_atomically.
void write_results_files(const std::filesystem::path& root, const ReplayResult& r,
                         const std::string& stats_json);

}  // namespace vigs::pipeline
