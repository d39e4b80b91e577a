#pragma once
// The one progress line `vigs run` keeps rewriting on a terminal (issue #14 item 6): frames,
// real-time factor, tracker p50/p99, ring drops, Gaussians and the time left. A replay's end is
// known (its frame count), so it gets an ETA at the rate played so far; a live source has no
// end and shows "live" there. Pure: no clock, no I/O, so it is tested as text.
#include <cstdint>
#include <optional>
#include <string>

#include "pipeline/live_pipeline.hpp"

namespace vigs::pipeline {

/// Seconds until the last of `frames_total` frames is played, at the wall rate so far
/// (frames_played / elapsed_s). nullopt when there is no end (frames_total 0: live) or no rate
/// yet (nothing played, no time elapsed); 0 once every frame is played.
std::optional<double> progress_eta_s(std::uint64_t frames_played, std::uint64_t frames_total,
                                     double elapsed_s);

/// "1:05" (m:ss) or "1:02:03" (h:mm:ss), rounded to the second; negative or non-finite as 0.
std::string format_duration_hms(double t_s);

/// The line without the leading '\r' or trailing '\n', e.g.
///   frames    40/80  rtf 1.00  tracker p50 3.1 / p99 5.2 ms  drops 0  gaussians 1200  ETA 0:02
/// A live source (frames_total 0) shows "frames    40" and "live" in place of the ETA.
std::string format_progress_line(const LiveProgress& p);

}  // namespace vigs::pipeline
