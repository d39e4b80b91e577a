#pragma once
// Where the simulator's streams go. The MCAP sink writes a recording; tests use an in-memory
// sink. Calls arrive in timestamp order (at equal stamps: IMU, ground truth, then the frame).
#include <cstdint>

#include "core/geometry/se3.hpp"
#include "core/types/imu_sample.hpp"
#include "core/types/pinhole_camera.hpp"
#include "sim/renderer.hpp"

namespace vigs::sim {

class SimSink {
 public:
  virtual ~SimSink() = default;
  /// One RGB-D frame at t_ns with its intrinsics (published as camera_info).
  virtual void frame(std::int64_t t_ns, const PinholeCamera& camera, const RgbdFrame& frame) = 0;
  virtual void imu(const ImuSample& sample) = 0;
  /// Ground-truth body (IMU) pose T_w_b.
  virtual void ground_truth(std::int64_t t_ns, const geometry::Pose& T_w_b) = 0;
};

}  // namespace vigs::sim
