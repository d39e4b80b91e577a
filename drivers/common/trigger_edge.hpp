// TriggerEdge: one rising edge of a camera's strobe / frame-sync line, stamped by the kernel.
// Produced by the gpio_trigger thread (drivers/gpio_trigger), consumed by a camera driver's
// TriggerMatcher and by the recorder's tap.
#pragma once

#include <cstdint>

namespace vigs::drivers {

struct TriggerEdge {
  std::int64_t t_ns = 0;       ///< CLOCK_MONOTONIC time of the edge (the kernel's event stamp)
  std::uint64_t sequence = 0;  ///< rising edges seen since start (gaps: edges dropped)
};

}  // namespace vigs::drivers
