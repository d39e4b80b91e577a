#pragma once
// Plots are drawn by Debian's gnuplot (package gnuplot-nox, pngcairo terminal): the report
// writes the data and a script, and gnuplot renders the PNGs.
#include <string>

namespace vigs::eval {

/// Runs `gnuplot SCRIPT` (stdout/stderr to LOG). Returns "" on success, else why not.
std::string run_gnuplot(const std::string& script_path, const std::string& log_path);

}  // namespace vigs::eval
