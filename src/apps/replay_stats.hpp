#pragma once
// stats.json of a replayed or live run (pipeline::ReplayResult): the keys pipeline::RunStats
// reads plus the odometry's counters. Shared by `vigs replay` and `vigs run`.
#include <string>

#include "io/json_text.hpp"
#include "pipeline/lockstep_replay.hpp"

namespace vigs::apps {

/// What a replay of a damaged recording used, for stderr and stats.json.
std::string used_of(const pipeline::ReplayResult& r);

/// Rates over no frames or no wall time are not defined and written as null.
io::Json stats_json(const pipeline::ReplayResult& r, const std::string& recording);

}  // namespace vigs::apps
