// TriggerMatcher: replaces a camera frame's stamp by the stamp of its frame-sync edge.
//
// A camera wired to a GPIO line pulses it at the start of each exposure; the kernel stamps the
// edge within microseconds, while the frame itself arrives (and is stamped) an exposure and a
// transfer later, with jitter. The driver thread calls match(t_frame_ns) for each frame, before
// it pushes the frame; the matcher first takes every edge queued by the gpio_trigger thread
// (its own SPSC ring; the matcher is that ring's only consumer) into a small window, then:
//  - an edge with t_edge + offset_ns < t_frame - tolerance_ns can match no frame any more (frame
//    stamps increase): it leaves the window as `edges_without_frame`;
//  - the window edge nearest t_frame - offset_ns, if within tolerance_ns, is the frame's edge:
//    match() returns its stamp (`matched`) and it leaves the window;
//  - otherwise the frame keeps its own stamp (`frames_without_edge`; match() returns nullopt).
// offset_ns is the expected frame stamp minus edge stamp (exposure + transfer; 0 when the camera
// driver's stamp is already the exposure start, as V4L2's SOE timestamps are); tolerance_ns is
// the largest accepted deviation and must stay under half a frame period so neighbours never
// match. A window full of edges (a camera that stopped, a line still pulsing) drops its oldest,
// counted as edges_without_frame.
// Driver thread only; counters() from any thread. No allocation, lock or log.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "drivers/common/trigger_edge.hpp"
#include "io/json_text.hpp"
#include "rt/counters.hpp"
#include "rt/spsc_ring.hpp"

namespace vigs::drivers {

struct TriggerMatchSettings {
  std::int64_t tolerance_ns = 3'000'000;  ///< |t_frame - offset - t_edge| accepted
  std::int64_t offset_ns = 0;             ///< expected t_frame - t_edge
};

struct TriggerMatchCounters {
  std::uint64_t matched = 0;              // frames restamped with their edge
  std::uint64_t frames_without_edge = 0;  // frames that kept their own stamp
  std::uint64_t edges_without_frame = 0;  // edges no frame claimed
};

/// {"matched": N, "frames_without_edge": N, "edges_without_frame": N} (stats.json).
[[nodiscard]] io::Json to_json_value(const TriggerMatchCounters& c);

/// From the robot config: camera.trigger_tolerance_ms, camera.trigger_offset_ms.
[[nodiscard]] inline TriggerMatchSettings trigger_match_settings(double tolerance_ms,
                                                                 double offset_ms) noexcept {
  return {.tolerance_ns = static_cast<std::int64_t>(tolerance_ms * 1e6),
          .offset_ns = static_cast<std::int64_t>(offset_ms * 1e6)};
}

class TriggerMatcher {
 public:
  static constexpr std::size_t kWindow = 32;

  TriggerMatcher(rt::SpscRing<TriggerEdge>& edges, const TriggerMatchSettings& settings);

  /// The edge stamp for a frame stamped t_frame_ns (stamps increasing), or nullopt.
  [[nodiscard]] std::optional<std::int64_t> match(std::int64_t t_frame_ns) noexcept;
  /// End of stream: every edge still waiting is counted as edges_without_frame.
  void finish() noexcept;
  [[nodiscard]] TriggerMatchCounters counters() const noexcept;
  [[nodiscard]] const TriggerMatchSettings& settings() const noexcept { return settings_; }

 private:
  void pull() noexcept;
  void erase(std::size_t i) noexcept;

  rt::SpscRing<TriggerEdge>& edges_;
  TriggerMatchSettings settings_;
  std::array<std::int64_t, kWindow> window_{};  // edge stamps, oldest first
  std::size_t size_ = 0;
  rt::SingleWriterCounter matched_, frames_without_edge_, edges_without_frame_;
};

}  // namespace vigs::drivers
