#pragma once
// Integer nanoseconds <-> builtin_interfaces/Time (int32 sec, uint32 nanosec in [0, 1e9)).
// Stamps stay integer from sensor to wire; negative times floor (t_ns = -1 -> sec -1,
// nanosec 999999999), as ROS 2's rclcpp::Time does.
#include <cstdint>
#include <limits>
#include <optional>

namespace vigs::dds {

struct RosTime {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
};

/// nullopt when t_ns is outside what int32 seconds can hold (about +-68 years).
[[nodiscard]] constexpr std::optional<RosTime> to_ros_time(std::int64_t t_ns) noexcept {
  constexpr std::int64_t kNsPerS = 1'000'000'000;
  std::int64_t sec = t_ns / kNsPerS;
  std::int64_t rem = t_ns % kNsPerS;
  if (rem < 0) {
    rem += kNsPerS;
    --sec;
  }
  if (sec < std::numeric_limits<std::int32_t>::min() ||
      sec > std::numeric_limits<std::int32_t>::max()) {
    return std::nullopt;
  }
  return RosTime{static_cast<std::int32_t>(sec), static_cast<std::uint32_t>(rem)};
}

[[nodiscard]] constexpr std::int64_t to_ns(std::int32_t sec, std::uint32_t nanosec) noexcept {
  return static_cast<std::int64_t>(sec) * 1'000'000'000 + static_cast<std::int64_t>(nanosec);
}

}  // namespace vigs::dds
