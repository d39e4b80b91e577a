#pragma once
#include <cstdint>

namespace vigs {

/// How a published pose was obtained.
enum class PoseSource : std::uint8_t {
  kTracked = 0,        ///< GICP converged against the local map
  kImuPropagated = 1,  ///< tracking failed; pose propagated with the IMU alone
  kGroundTruth = 2,    ///< from a simulator or dataset
};

/// Camera or body pose at one instant. Plain data for rings, DDS and recordings.
struct PoseStamped {
  std::int64_t t_ns = 0;
  double p_w_m[3] = {};               ///< position in world, m
  double q_w_xyzw[4] = {0, 0, 0, 1};  ///< orientation in world, quaternion x y z w
  PoseSource source = PoseSource::kTracked;
  double covariance[36] = {};  ///< 6x6 row-major, [x y z rx ry rz], m^2 / rad^2
};

}  // namespace vigs
