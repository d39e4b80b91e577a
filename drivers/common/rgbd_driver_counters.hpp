// Counters of an RGB-D driver thread, as one snapshot (Openni2Driver::counters(),
// V4l2RgbdDriver::counters().rgbd).
//
// Bookkeeping that always holds once the driver has stopped (and at any quiet moment):
//   frames_read == delivered + dropped_ring_full + dropped_pool_empty
// and every depth or colour frame read is exactly one of: part of a pair, unpaired, or
// size_mismatch (a frame still pending at stop is neither).
#pragma once

#include <cstdint>

#include "io/json_text.hpp"

namespace vigs::drivers {

struct RgbdDriverCounters {
  std::uint64_t depth_read = 0;          // depth frames returned by readFrame
  std::uint64_t colour_read = 0;         // colour frames returned by readFrame
  std::uint64_t frames_read = 0;         // depth+colour pairs formed (RGB-D frames)
  std::uint64_t delivered = 0;           // pairs pushed into the ring
  std::uint64_t dropped_ring_full = 0;   // pairs dropped: ring full (newest dropped, slot freed)
  std::uint64_t dropped_pool_empty = 0;  // pairs dropped: no free FramePool slot
  std::uint64_t unpaired = 0;            // depth or colour frames that found no partner
  std::uint64_t size_mismatch = 0;       // frames whose size/format differs from the camera's
  std::uint64_t read_errors = 0;         // waitForAnyStream / readFrame failures
  std::uint64_t timeouts = 0;            // waits that saw no frame within wait_timeout_ms
  std::uint64_t clock_reanchors = 0;     // device time went backwards (DeviceClock)
  std::uint64_t playback_skipped = 0;    // .oni playback: depth frames OpenNI2's player
                                         // replaced (or wrapped past at the clip's end) before
                                         // the driver read them (0 in manual mode, the driver's)
  // Life cycle (DeviceStateMachine): one counter per fault kind.
  std::uint64_t opens = 0;           // successful opens (start() included)
  std::uint64_t open_failures = 0;   // failed (re)open attempts
  std::uint64_t losses = 0;          // streams lost = frame_timeouts + error_resets + device_gone
  std::uint64_t frame_timeouts = 0;  // no frame within frame_timeout_ms (playback stalled)
  std::uint64_t error_resets = 0;    // max_consecutive_errors failures in a row forced a reset
  std::uint64_t device_gone = 0;     // the device vanished
  std::uint64_t reopens = 0;         // opens after a loss (opens - 1 once started)
  std::uint64_t tap_dropped = 0;     // recorder tap full: a delivered or dropped pair not recorded
  bool end_of_stream = false;        // the stream has ended (clip end or final fault)
};

/// {"depth_read": N, ..., "end_of_stream": B} (`vigs rgbd play`, `vigs run`'s stats.json).
[[nodiscard]] io::Json to_json_value(const RgbdDriverCounters& c);

}  // namespace vigs::drivers
