// FramePairer: pairs depth frames with colour frames by device timestamp, without OpenNI2.
//
// The driver reads the two streams one frame at a time, in whatever order they become ready. It
// keeps at most one pending frame per stream; this class decides, from their device timestamps
// alone, what to do with them:
//  - both pending and |t_depth - t_colour| <= tolerance: pair them (both leave);
//  - both pending and farther apart: the older one can only get farther from any later partner,
//    so it leaves unpaired (the newer one stays and waits for its partner);
//  - a stream delivers a new frame while its previous one still waits: the previous one leaves
//    unpaired (add_* returns true) and the new one waits instead.
// The caller mirrors each decision on the frames it holds and counts the unpaired ones.
// All members are noexcept and allocation-free (real-time path).
#pragma once

#include <cstdint>

namespace vigs::drivers {

enum class PairStep : std::uint8_t {
  kWait,           // nothing to do until the other stream delivers
  kPair,           // pair the pending depth and colour frames; both slots are now empty
  kDiscardDepth,   // the pending depth frame is unpaired (older, too far from the colour)
  kDiscardColour,  // the pending colour frame is unpaired (older, too far from the depth)
};

class FramePairer {
 public:
  // tolerance_us: largest |t_depth - t_colour| still paired (the driver uses half a frame period).
  explicit FramePairer(std::int64_t tolerance_us) noexcept : tolerance_us_(tolerance_us) {}

  // A new frame of each stream. Returns true when it displaced a still-pending frame of the same
  // stream (that one is unpaired).
  bool add_depth(std::int64_t t_device_us) noexcept { return add(depth_, t_device_us); }
  bool add_colour(std::int64_t t_device_us) noexcept { return add(colour_, t_device_us); }

  // Applies and returns the next decision (see the header comment). Call after every add_*; at
  // most one call returns something other than kWait per add_*.
  PairStep step() noexcept;

  [[nodiscard]] bool depth_pending() const noexcept { return depth_.pending; }
  [[nodiscard]] bool colour_pending() const noexcept { return colour_.pending; }
  [[nodiscard]] std::int64_t tolerance_us() const noexcept { return tolerance_us_; }
  // Forgets both pending frames (start of a new stream).
  void reset() noexcept { depth_ = colour_ = {}; }

 private:
  struct Slot {
    bool pending = false;
    std::int64_t t_device_us = 0;
  };
  static bool add(Slot& s, std::int64_t t_device_us) noexcept {
    const bool displaced = s.pending;
    s = {true, t_device_us};
    return displaced;
  }

  std::int64_t tolerance_us_;
  Slot depth_;
  Slot colour_;
};

}  // namespace vigs::drivers
