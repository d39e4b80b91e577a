#pragma once
// StatusSnapshot (plain data from the pipeline) -> vigs_msgs::msg::dds_::Status_.
#include <string>

#include "dds/status_snapshot.hpp"
#include "vigs_msgs.h"

namespace vigs::dds {

/// False (nothing to publish) when the snapshot's stamp does not fit builtin_interfaces/Time.
/// Table counts are clamped to the table sizes; non-finite doubles become 0.
bool fill_status(const StatusSnapshot& s, const std::string& robot, const std::string& frame_id,
                 vigs_msgs::msg::dds_::Status_& out);

}  // namespace vigs::dds
