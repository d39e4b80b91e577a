#pragma once
// Plots are drawn by Debian's gnuplot (package gnuplot-nox, pngcairo terminal): the report
// writes the data and a script, and gnuplot renders the PNGs.
#include <string>

namespace vigs::eval {

/// Runs `gnuplot SCRIPT` (stdout/stderr to LOG) in the folder `work_dir` (empty: this
/// process's), so a script naming its files relative to its own folder draws them there.
/// Returns "" on success, else why not.
std::string run_gnuplot(const std::string& script_path, const std::string& log_path,
                        const std::string& work_dir = {});

}  // namespace vigs::eval
