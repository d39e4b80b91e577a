#pragma once
// StatusSnapshot: what the live pipeline reports once per status period, as plain fixed-size
// data with no DDS types, so the pipeline can fill it without linking DDS and hand it over
// through an rt::OverwriteRing<StatusSnapshot> (capacity 1: a latest-value mailbox; the producer
// never blocks, an unread snapshot is simply replaced). The DDS publisher thread turns the newest
// one into a vigs_msgs::msg::dds_::Status_ on <topic_prefix>/status at 1 Hz
// (src/dds/idl/vigs_msgs.idl, its ROS 2 twin src/dds/msg/Status.msg).
//
// Filling rules: names are NUL-terminated and truncated to fit (set_name does this); only the
// first *_count entries of each table are published; non-finite doubles are published as 0.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <type_traits>

namespace vigs::dds {

/// Status.msg TRACKING_STATE_* values.
enum class TrackingState : std::uint8_t {
  kStarting = 0,  ///< no pose yet
  kTracking = 1,  ///< GICP (fused with the IMU prediction) succeeds
  kImuOnly = 2,   ///< tracking failed; the pose is propagated with the IMU
  kLost = 3,      ///< neither tracking nor IMU propagation
};

inline constexpr std::size_t kStatusNameLength = 32;  ///< bytes including the NUL

/// Copies `name` into a fixed char array, truncating, always NUL-terminated.
inline void set_name(char (&dst)[kStatusNameLength], std::string_view name) noexcept {
  const std::size_t n = std::min(name.size(), kStatusNameLength - 1);
  std::memcpy(dst, name.data(), n);
  dst[n] = '\0';
}

struct ThreadStatusEntry {
  char name[kStatusNameLength] = {};  ///< rt/thread_table.hpp name
  double rate_hz = 0;                 ///< cycles in the last period / its length, Hz
  std::int64_t cycle_p50_ns = 0;      ///< body run time median, ns
  std::int64_t cycle_p99_ns = 0;      ///< body run time 99th percentile, ns
  std::uint64_t overruns = 0;         ///< cycles that ended after their next deadline
  std::uint64_t missed_deadlines = 0;
};

struct RingStatusEntry {
  char name[kStatusNameLength] = {};  ///< e.g. "imu->tracker"
  std::uint32_t depth = 0;            ///< elements queued at snapshot time
  std::uint32_t capacity = 0;         ///< elements
  std::uint64_t drops = 0;            ///< dropped or overwritten by the full policy
};

struct FaultCounterEntry {
  char name[kStatusNameLength] = {};  ///< e.g. "imu.checksum_errors"
  std::uint64_t count = 0;
};

struct StatusSnapshot {
  static constexpr std::size_t kMaxThreads = 8;
  static constexpr std::size_t kMaxRings = 8;
  static constexpr std::size_t kMaxFaults = 24;

  std::int64_t t_ns = 0;  ///< when the snapshot was taken (the pipeline's clock), ns
  TrackingState tracking_state = TrackingState::kStarting;
  std::uint64_t frames_tracked = 0;  ///< poses produced since start
  std::uint64_t gaussian_count = 0;  ///< Gaussians in the map
  double mapping_budget_used = 0;    ///< mapper tick time / tick budget, last period
  std::uint32_t thread_count = 0;    ///< valid entries in threads
  std::uint32_t ring_count = 0;      ///< valid entries in rings
  std::uint32_t fault_count = 0;     ///< valid entries in faults
  ThreadStatusEntry threads[kMaxThreads];
  RingStatusEntry rings[kMaxRings];
  FaultCounterEntry faults[kMaxFaults];
};
static_assert(std::is_trivially_copyable_v<StatusSnapshot>, "rt::OverwriteRing copies raw words");

}  // namespace vigs::dds
