#include "drivers/common/rgbd_driver_counters.hpp"

namespace vigs::drivers {

io::Json to_json_value(const RgbdDriverCounters& c) {
  return {{"depth_read", c.depth_read},
          {"colour_read", c.colour_read},
          {"frames_read", c.frames_read},
          {"delivered", c.delivered},
          {"dropped_ring_full", c.dropped_ring_full},
          {"dropped_pool_empty", c.dropped_pool_empty},
          {"unpaired", c.unpaired},
          {"size_mismatch", c.size_mismatch},
          {"read_errors", c.read_errors},
          {"timeouts", c.timeouts},
          {"clock_reanchors", c.clock_reanchors},
          {"playback_skipped", c.playback_skipped},
          {"opens", c.opens},
          {"open_failures", c.open_failures},
          {"losses", c.losses},
          {"frame_timeouts", c.frame_timeouts},
          {"error_resets", c.error_resets},
          {"device_gone", c.device_gone},
          {"reopens", c.reopens},
          {"end_of_stream", c.end_of_stream}};
}

}  // namespace vigs::drivers
