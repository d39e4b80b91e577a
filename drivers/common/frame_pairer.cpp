#include "drivers/common/frame_pairer.hpp"

namespace vigs::drivers {

PairStep FramePairer::step() noexcept {
  if (!depth_.pending || !colour_.pending) return PairStep::kWait;
  const std::int64_t dt_us = depth_.t_device_us - colour_.t_device_us;
  if (dt_us <= tolerance_us_ && -dt_us <= tolerance_us_) {
    depth_.pending = colour_.pending = false;
    return PairStep::kPair;
  }
  // Too far apart: the older frame can only be farther from any partner still to come.
  if (dt_us < 0) {
    depth_.pending = false;
    return PairStep::kDiscardDepth;
  }
  colour_.pending = false;
  return PairStep::kDiscardColour;
}

}  // namespace vigs::drivers
